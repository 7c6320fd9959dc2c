# The reflection tracer: voxel grid, voxel walk, foreground pyramids, the frame renderer's passes
# one at a time (test_frame_passes, on the internal headers of reflect/src) and end to end.
holo_test(test_tracer
  SOURCES test_voxel_grid.cpp test_voxel_walk.cpp test_foreground_pyramid.cpp test_frame_passes.cpp
          test_frame_renderer.cpp test_frame_renderer_reuse.cpp test_frame_renderer_accuracy.cpp
          test_rough_foreground_map.cpp
  DEPS holo::reflect holo::depthfilter holo_test_support)
target_include_directories(test_tracer PRIVATE ${PROJECT_SOURCE_DIR}/reflect/src)
holo_benchmark(bench_voxel_walk
  SOURCES bench_voxel_walk.cpp
  DEPS holo::reflect holo::depthfilter holo_test_support)
# Against path-traced ground truth on a simulated museum frame (needs module sim).
if(TARGET holo::sim)
  holo_test(test_tracer_vs_path_traced
    SOURCES test_tracer_vs_path_traced.cpp
    DEPS holo::reflect holo::sim holo_test_support)
endif()
holo_benchmark(bench_frame_renderer
  SOURCES bench_frame_renderer.cpp
  DEPS holo::reflect holo::depthfilter holo_test_support)
# The evaluation's baselines: SSRT and the voxel emitters of the MCPT baseline.
holo_test(test_baselines
  SOURCES test_ssrt.cpp
  DEPS holo::reflect holo::depthfilter holo_test_support)
# Issue 5's fg_mse bars on one small scene (gallery, bronze vase, 96^2, paper's region threshold):
# ours at most a quarter of IBL's and below SSRT's (fixed rays: the equal-time pick would depend
# on the load). The walkers only, seen by the default rig (no close visitor, tilt 8, vfov 70), 7
# levels: where the bars hold; with a visitor close to the pyramid they do not yet (docs/tracer.md).
# The nine scenes: holopyramid eval tracer.
add_test(NAME reflect_eval_tracer_small
  COMMAND $<TARGET_FILE:holopyramid> eval tracer --halls gallery --relics vase --size 96 --gt-spp 256
          --mcpt-max-spp 16 --floor-spp 64 --repeats 1 --ssrt-rays 1 --require-fg-bars
          --close-visitors 0 --camera-tilt-deg 8 --camera-vfov-deg 70 --levels 7
          --out ${CMAKE_CURRENT_BINARY_DIR}/eval_tracer --cache ${CMAKE_CURRENT_BINARY_DIR}/gt-cache
  WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
set_tests_properties(reflect_eval_tracer_small PROPERTIES LABELS reflect TIMEOUT 300)
