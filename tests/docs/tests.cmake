# Every command of the README's sh blocks, run verbatim in a fresh directory with a fresh HOME
# (install into ~/.local, real POV-Ray and Blender renders): it uses both cores, so runs alone.
add_python_test(docs.readme_commands docs/test_readme_commands.py)
set_tests_properties(docs.readme_commands PROPERTIES TIMEOUT 1200 PROCESSORS 2 LABELS docs)
