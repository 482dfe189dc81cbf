import os

from hypothesis import HealthCheck, settings

from tests.warm import safe_numba_cache

settings.register_profile("dev", max_examples=60, deadline=None)
settings.register_profile("ci", max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow], derandomize=True)
settings.register_profile("thorough", max_examples=2000, deadline=None, suppress_health_check=[HealthCheck.too_slow])
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "dev"))

# Every worker may compile a kernel specialisation the warm-up did not: numba's cache made
# safe for processes compiling side by side (see tests.warm.safe_numba_cache).
safe_numba_cache()

# The commands and inner pytest runs the tests start share compiled (and pytest's
# rewritten) modules, as they would on a user's machine, even where the environment
# says not to write them (each would otherwise compile every module again: seconds each).
os.environ.pop("PYTHONDONTWRITEBYTECODE", None)

# The longest modules first: `make test` hands whole modules to its workers in collection
# order (--dist loadfile), so a long module collected last would leave one worker running
# it alone at the end.
# (CPU seconds each, measured: identify 45, oracle 22, runner 18, known_bad 17, registry_and_cli
# 17, aa_references 13, fingerprints 12, area 12, coverage_identify 12, cli_run 11, browser 11,
# pytest_plugin 11; every other module 10 or less)
LONGEST_FIRST = ["test_identify.py", "test_oracle.py", "test_runner.py", "test_known_bad.py", "test_registry_and_cli.py",
                 "test_aa_references.py", "test_fingerprints.py", "test_area.py", "test_coverage_identify.py", "test_cli_run.py",
                 "test_browser.py", "test_pytest_plugin.py"]


def pytest_collection_modifyitems(items):
    def rank(item):
        name = item.path.name
        return LONGEST_FIRST.index(name) if name in LONGEST_FIRST else len(LONGEST_FIRST)

    items.sort(key=rank)  # stable: each module keeps its own order
