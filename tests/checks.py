"""The check harness of libbrdf's script tests (tests/blender, tests/povray, tests/main_job).

    sys.path.insert(0, TESTS_DIR)
    import checks
    checks.check(condition, message)   # records one check; returns bool(condition)
    checks.finish("ok: ...")           # prints the summary and exits (1 on any failure)

check() prints "FAIL MESSAGE" for a failed check and "ok   MESSAGE" for one that holds, unless the
script set `checks.print_passes = False` (scripts whose messages describe the problem, not the
property). finish() lists the failures on stderr, prints its message when all held, then
"N passed, M failed" alone on the last line of stdout, and exits with status 1 on any failure, else 0.
"""

import sys

print_passes = True
passed = 0
failures = []


def check(condition, message):
    global passed
    ok = bool(condition)
    if ok:
        passed += 1
        if print_passes:
            print("ok   " + message, flush=True)
    else:
        failures.append(message)
        print("FAIL " + message, flush=True)
    return ok


def finish(success_message=None, context=""):
    """Exits: status 1 if any check failed (the failures listed on stderr, `context` after the
    count, e.g. " in OUT"), else 0 after printing `success_message`."""
    if failures:
        print(f"FAIL: {len(failures)} check(s) failed{context}:", *failures, sep="\n  ", file=sys.stderr, flush=True)
    elif success_message:
        print(success_message)
    print(f"{passed} passed, {len(failures)} failed", flush=True)
    sys.exit(1 if failures else 0)
