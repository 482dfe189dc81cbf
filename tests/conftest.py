import gc
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
# order (--dist loadfile --no-loadscope-reorder), so a long module collected last would
# leave one worker running it alone at the end.
# (seconds of test time each on a fresh clone, 3 workers on 2 cores, measured per test:
# identify 31, known_bad 26, campaign 21, runner 20, fingerprints 20, peer_freetype 19 (its
# kernels compile in it), registry_and_cli 17, coverage_identify 16, area_checks 16,
# signatures 15, hostile 15, peer_deqp 14, time_limits 13, peer_stb 13, gl_lines 11,
# line_direction 11, area 10, browser 10, pytest_plugin 9, identify_agrees 9,
# line_identify 8, msaa_lines 8; every other module less)
LONGEST_FIRST = ["test_identify.py", "test_known_bad.py", "test_campaign.py", "test_runner.py", "test_fingerprints.py",
                 "test_peer_freetype.py", "test_registry_and_cli.py", "test_coverage_identify.py", "test_area_checks.py",
                 "test_signatures.py", "test_hostile.py", "test_peer_deqp.py", "test_time_limits.py", "test_peer_stb.py",
                 "test_gl_lines.py", "test_line_direction.py", "test_area.py", "test_browser.py", "test_pytest_plugin.py",
                 "test_identify_agrees.py", "test_line_identify.py", "test_msaa_lines.py"]


def pytest_collection_modifyitems(items):
    def rank(item):
        name = item.path.name
        return LONGEST_FIRST.index(name) if name in LONGEST_FIRST else len(LONGEST_FIRST)

    items.sort(key=rank)  # stable: each module keeps its own order


def pytest_collection_finish(session):
    # Everything imported and collected so far lives to the end of the run: moved out of the
    # garbage collector's reach, so its full collections walk only what the tests make
    # (they took 3 s of each worker's CPU, walking numba's, scipy's and hypothesis's objects).
    gc.freeze()
