# The main job (./run.sh) at reduced size, end to end: bakes, Fig. 2, model plots, bench, POV-Ray
# and Blender renders, index.html. It uses both cores for minutes, so ctest runs it alone
# (PROCESSORS 2) rather than beside the other render tests.
add_python_test(main_job.small_report main_job/test_main_job.py)
set_tests_properties(main_job.small_report PROPERTIES TIMEOUT 1800 PROCESSORS 2 LABELS main_job)
