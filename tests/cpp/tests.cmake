# Core library tests (issue #2): physics identities, series accuracy, renormalization, hard cases.
# One GoogleTest executable; every TEST is its own ctest entry (gtest_discover_tests).
add_libbrdf_test(libbrdf_core_tests
  ${CMAKE_CURRENT_LIST_DIR}/test_geometry.cpp
  ${CMAKE_CURRENT_LIST_DIR}/test_fresnel.cpp
  ${CMAKE_CURRENT_LIST_DIR}/test_series.cpp
  ${CMAKE_CURRENT_LIST_DIR}/test_renormalization.cpp
  ${CMAKE_CURRENT_LIST_DIR}/test_models.cpp
  ${CMAKE_CURRENT_LIST_DIR}/test_materials.cpp
  ${CMAKE_CURRENT_LIST_DIR}/test_hostile_input.cpp
  ${CMAKE_CURRENT_LIST_DIR}/test_kernel_table.cpp)
target_link_libraries(libbrdf_core_tests PRIVATE hwy::hwy)  # hwy: the per-target checks
