// Built into every test program of a ThreadSanitizer build (cmake/HoloModule.cmake). oneTBB's
// workers hand their results back inside libtbb, which Debian does not build with TSan, so TSan
// reports each hand-over (a parallel loop's output read after it returns, the loop's context
// rebuilt on the caller's stack) as a race whose other stack it cannot restore, and no
// suppression can name it. With one thread, TBB runs every algorithm on the calling thread and
// TSan checks the threads that are ours: capture threads, mailboxes, the overlapped foreground
// worker and the kiosk's threads.
#include <tbb/global_control.h>

namespace {
const tbb::global_control kOneTbbThread(tbb::global_control::max_allowed_parallelism, 1);
}  // namespace
