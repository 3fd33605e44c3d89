# The `brdf eval` contract (issue #2): CSV format, query input, every model name, error handling.
add_python_test(cli_eval_contract cli/test_eval_contract.py)
# Hostile input (issue 11): the issue's reproducers -- ranges, one rule for values, signals, caps, albedo.
add_python_test(cli_hostile_input cli/test_hostile_input.py)
# The independent ASF audit (tools/audit/asf_reference_audit.py, --quick: 91 surface and query sets,
# ~1.5e5 values against its own log-space reference of eq. 11, at --tolerance 1e-6 and 1e-4, auto
# and series; polar angles to 89.99999999999 deg; bad inputs). ~30 s of CPU.
add_python_test(cli_asf_reference_audit ../tools/audit/asf_reference_audit.py --brdf $<TARGET_FILE:brdf> --quick)
