# Baked tables (issue #3): layouts, bake and its measured error, --target-error, OpenEXR and MERL
# files (round trips, an independent MERL reader, corrupt/truncated/foreign files), cancellation.
# Included by tests/CMakeLists.txt.
add_libbrdf_test(libbrdf_lut_tests ${CMAKE_CURRENT_LIST_DIR}/test_lut.cpp)
target_link_libraries(libbrdf_lut_tests PRIVATE OpenImageIO::OpenImageIO hwy::hwy)  # hwy: the per-target checks
# The CLI side: brdf bake / brdf eval --lut / brdf bench, SIGINT, exit statuses, the MERL binary
# read by the test's own reader written from the format's published layout.
add_python_test(lut_cli lut/test_lut_cli.py)
set_tests_properties(lut_cli PROPERTIES TIMEOUT 300)
