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
# (seconds of test time each, 3 workers on 2 cores, measured per test: identify 41, runner 23,
# known_bad 22, campaign 22, registry_and_cli 21, fingerprints 19, signatures 17,
# coverage_identify 15, pytest_plugin 15, identify_agrees 14, hostile 14, peer_freetype 13,
# time_limits 13, area_checks 13, browser 12, path_cases 12, line_direction 11, peer_deqp 9,
# winding 9, gl_lines 8, cli_run 8, line_identify 8; every other module less)
LONGEST_FIRST = ["test_identify.py", "test_runner.py", "test_known_bad.py", "test_campaign.py", "test_registry_and_cli.py",
                 "test_fingerprints.py", "test_signatures.py", "test_coverage_identify.py", "test_pytest_plugin.py",
                 "test_identify_agrees.py", "test_hostile.py", "test_peer_freetype.py", "test_time_limits.py",
                 "test_area_checks.py", "test_browser.py", "test_path_cases.py", "test_line_direction.py",
                 "test_peer_deqp.py", "test_winding.py", "test_gl_lines.py", "test_cli_run.py", "test_line_identify.py"]


def pytest_collection_modifyitems(items):
    def rank(item):
        name = item.path.name
        return LONGEST_FIRST.index(name) if name in LONGEST_FIRST else len(LONGEST_FIRST)

    items.sort(key=rank)  # stable: each module keeps its own order
