# POV-Ray export (issue #4): the exporter's table, fit and include (GoogleTest, no POV-Ray), the
# `brdf export povray` contract, real POV-Ray renders of NAME_Exact against `brdf eval`, and the
# comparison tool at reduced size.
add_libbrdf_test(povray_exporter_tests ${CMAKE_CURRENT_LIST_DIR}/test_povray_exporter.cpp)
target_link_libraries(povray_exporter_tests PRIVATE libbrdf_exporters)
add_python_test(povray.export_cli povray/test_export_cli.py)
add_python_test(povray.exact_render povray/test_exact_render.py)
add_python_test(povray.comparison_tool povray/test_comparison_tool.py)
# NAME_Fit (issue 10): the fitted Blinn and Phong lobes rendered by POV-Ray against brdf eval, one sun.
add_python_test(povray.fit_render povray/test_fit_render.py)
# NAME_Fit at seeded random suns, cameras and surfaces (issue 33; tests/fit_bands.py).
add_python_test(povray.fit_random povray/test_fit_random.py)
set_tests_properties(povray.export_cli povray.exact_render povray.comparison_tool povray.fit_render povray.fit_random
                     PROPERTIES LABELS povray TIMEOUT 600)
# Issue 34: every include's usage comment, rendered verbatim (NAME_Exact, and NAME_Fit under a sun),
# shows the lit object brdf eval predicts; the old comment's camera (-100*View_Direction) fails the check.
add_python_test(povray.include_usage povray/test_include_usage.py)
set_tests_properties(povray.include_usage PROPERTIES LABELS povray TIMEOUT 600)
