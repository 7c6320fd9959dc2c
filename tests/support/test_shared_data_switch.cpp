// The helper behind the shared_data_* tests: one test that needs a file of the shared data. With
// HOLO_SHARED_DATA pointing nowhere it must skip, or fail when HOLO_REQUIRE_SHARED_DATA=1.
#include <gtest/gtest.h>

#include "shared_data.hpp"

TEST(SharedData, TheReadmeIsThere) {
  HOLO_REQUIRE_SHARED_DATA("README.md");
  EXPECT_TRUE(std::filesystem::is_regular_file(holo::test::sharedData("README.md")));
}
