# `cmake --install` into a temporary prefix, then a consumer project built against it with Debian's
# /usr/bin/cmake (find_package(libbrdf)), the installed brdf and the installed Python module.
add_python_test(install.consumer install/test_install.py --cmake ${CMAKE_COMMAND})
set_tests_properties(install.consumer PROPERTIES TIMEOUT 600 LABELS install)
