# The `brdf eval` contract (issue #2): CSV format, query input, every model name, error handling.
add_python_test(cli_eval_contract cli/test_eval_contract.py)
