import gc
import os
from pathlib import Path

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
LONGEST_FIRST = ["identify/test_fingerprint.py", "acceptance/test_known_bad.py", "campaign/test_campaign.py",
                 "engine/test_runner.py", "identify/test_triangle_probes.py", "peers/test_freetype.py", "engine/test_registry.py",
                 "identify/test_coverage_probes.py", "checks/test_area.py", "diagnose/test_signatures.py",
                 "acceptance/test_hostile.py", "peers/test_deqp.py", "engine/test_isolation.py", "peers/test_stb.py",
                 "oracle/test_gl_lines.py", "oracle/test_line_direction.py", "oracle/test_area.py", "acceptance/test_browser.py",
                 "integrations/test_pytest_plugin.py", "identify/test_agrees_with_run.py", "identify/test_line_probes.py",
                 "oracle/test_msaa_lines.py"]


def pytest_collection_modifyitems(items):
    tests = Path(__file__).parent

    def rank(item):
        name = item.path.relative_to(tests).as_posix() if item.path.is_relative_to(tests) else item.path.name
        return LONGEST_FIRST.index(name) if name in LONGEST_FIRST else len(LONGEST_FIRST)

    items.sort(key=rank)  # stable: each module keeps its own order


def pytest_collection_finish(session):
    # Everything imported and collected so far lives to the end of the run: moved out of the
    # garbage collector's reach, so its full collections walk only what the tests make
    # (they took 3 s of each worker's CPU, walking numba's, scipy's and hypothesis's objects).
    gc.freeze()
