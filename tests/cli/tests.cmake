# The `brdf eval` contract (issue #2): CSV format, query input, every model name, error handling.
add_python_test(cli_eval_contract cli/test_eval_contract.py)
# Hostile input (issue 11): the issue's reproducers -- ranges, one rule for values, signals, caps, albedo.
add_python_test(cli_hostile_input cli/test_hostile_input.py)
