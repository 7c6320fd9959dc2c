#include "static_pass_schedule.hpp"

#include <algorithm>

namespace holo::reflect {

std::vector<StaticPass> scheduleStaticPasses(const std::vector<ViewReuseState>& views,
                                             int retraces_per_frame) {
  std::vector<StaticPass> passes(views.size(), StaticPass::Trace);
  std::vector<std::size_t> waiting;
  int forced = 0;
  for (std::size_t v = 0; v < views.size(); ++v) {
    const ViewReuseState& s = views[v];
    if (s.cache_shown && s.within_reuse)
      passes[v] = StaticPass::Reuse;
    else if (retraces_per_frame > 0 && s.cache_shown && s.within_defer)
      waiting.push_back(v);
    else
      ++forced;
  }
  std::stable_sort(waiting.begin(), waiting.end(), [&](std::size_t a, std::size_t b) {
    if (views[a].waited != views[b].waited) return views[a].waited > views[b].waited;
    return views[a].moved > views[b].moved;
  });
  const std::size_t traced = std::size_t(std::max(retraces_per_frame - forced, 0));
  for (std::size_t k = traced; k < waiting.size(); ++k) passes[waiting[k]] = StaticPass::Defer;
  return passes;
}

}  // namespace holo::reflect
