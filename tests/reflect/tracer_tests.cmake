# The reflection tracer: voxel grid, voxel walk, foreground pyramids, the frame renderer's passes
# one at a time (test_frame_passes, on the internal headers of reflect/src) and end to end.
holo_test(test_tracer
  SOURCES test_voxel_grid.cpp test_voxel_walk.cpp test_foreground_pyramid.cpp test_frame_passes.cpp
          test_frame_renderer.cpp test_frame_renderer_reuse.cpp test_frame_renderer_accuracy.cpp
          test_rough_foreground_map.cpp
  DEPS holo::reflect holo::reference holo::depthfilter holo_test_support)
target_include_directories(test_tracer PRIVATE ${PROJECT_SOURCE_DIR}/reflect/src)
holo_benchmark(bench_voxel_walk
  SOURCES bench_voxel_walk.cpp
  DEPS holo::reflect holo::depthfilter holo_test_support)
# Against path-traced ground truth on a simulated museum frame (needs module sim).
if(TARGET holo::sim)
  holo_test(test_tracer_vs_path_traced
    SOURCES test_tracer_vs_path_traced.cpp
    DEPS holo::reflect holo::reference holo::sim holo_test_support)
endif()
holo_benchmark(bench_frame_renderer
  SOURCES bench_frame_renderer.cpp
  DEPS holo::reflect holo::depthfilter holo_test_support)
# The refraction pass, the clearcoat and the effect plan's material passes (reflect/src internals).
holo_test(test_refraction
  SOURCES test_refraction.cpp
  DEPS holo::reflect holo::reference holo::depthfilter holo_test_support)
target_include_directories(test_refraction PRIVATE ${PROJECT_SOURCE_DIR}/reflect/src)
# The relic's self-occlusion and the rough interreflection's lobe on the concave bowl, against
# path-traced truth (needs the built-in relics).
if(TARGET holo::relics)
  holo_test(test_self_occlusion
    SOURCES test_self_occlusion.cpp
    DEPS holo::reflect holo::reference holo::relics holo_test_support)
endif()
# Progressive refinement of the rough interreflection while nothing moves, on the metal bowl
# (needs the built-in relics).
if(TARGET holo::relics)
  holo_test(test_progressive_refinement
    SOURCES test_progressive_refinement.cpp
    DEPS holo::reflect holo::relics holo::depthfilter holo_test_support)
  target_include_directories(test_progressive_refinement PRIVATE ${PROJECT_SOURCE_DIR}/reflect/src)
endif()
# The axis-aligned filter of the rough lobe's interreflection against path-traced truth.
if(TARGET holo::relics)
  holo_test(test_axis_aligned_filter
    SOURCES test_axis_aligned_filter.cpp
    DEPS holo::reflect holo::reference holo::relics holo_test_support)
  target_include_directories(test_axis_aligned_filter PRIVATE ${PROJECT_SOURCE_DIR}/reflect/src)
endif()

# Where the interreflection casts rays on the built-in relics: conservative (brute force) and counted.
if(TARGET holo::relics)
  holo_test(test_interreflection_plan
    SOURCES test_interreflection_plan.cpp
    DEPS holo::reflect holo::relics holo_test_support)
  target_include_directories(test_interreflection_plan PRIVATE ${PROJECT_SOURCE_DIR}/reflect/src)
endif()
# The panorama's sun as a directional light: the closed-form crescent and the counters (needs the
# built-in relics and the simulated halls).
if(TARGET holo::relics AND TARGET holo::sim)
  holo_test(test_sun_light
    SOURCES test_sun_light.cpp
    DEPS holo::reflect holo::relics holo::sim holo_test_support)
  target_include_directories(test_sun_light PRIVATE ${PROJECT_SOURCE_DIR}/reflect/src)
endif()
