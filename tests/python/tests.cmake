# The Python module (issue 12): the same numbers as `brdf eval`, and its array contract.
# The tests import it from its build directory (no install), as the README's set-up says.
if(TARGET libbrdf_python)
  add_python_test(python_eval_contract python/test_python_contract.py)
  add_python_test(python_module python/test_python_module.py)
  set_property(TEST python_eval_contract python_module APPEND PROPERTY ENVIRONMENT
               "PYTHONPATH=${PROJECT_BINARY_DIR}/python")
endif()
# The package's install component (what pyproject.toml's wheel holds), installed and imported
# outside the source and build trees (issue 33).
if(TARGET libbrdf_python)
  add_python_test(python_package_install python/test_python_install.py)
endif()
