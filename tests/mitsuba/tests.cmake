# Mitsuba 3 (issue 36): libbrdf.mitsuba's plugins checked by Mitsuba's own chi2 test, a white
# furnace against `brdf albedo` and one sun on a sphere against `brdf eval`, in the pinned venv of
# scripts/python_env.sh mitsuba (skipped, exit 77, with the reason where none can be made). One at
# a time (RESOURCE_LOCK): they share the venv, which the first one may still be creating.
if(TARGET libbrdf_python)
  foreach(name chi2 furnace sun_sphere)
    add_test(NAME mitsuba_${name} COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/mitsuba/run_in_venv.sh
             ${CMAKE_CURRENT_SOURCE_DIR}/mitsuba/test_mitsuba_${name}.py)
    set_tests_properties(mitsuba_${name} PROPERTIES
      ENVIRONMENT "BRDF_EXE=$<TARGET_FILE:brdf>;PYTHONPATH=${PROJECT_BINARY_DIR}/python;LIBBRDF_ROOT=${PROJECT_SOURCE_DIR}"
      SKIP_RETURN_CODE 77 RESOURCE_LOCK mitsuba_venv LABELS mitsuba TIMEOUT 600)
  endforeach()
endif()
