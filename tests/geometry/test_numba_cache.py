"""numba's on-disk cache shared by processes that start side by side (harness.geometry.numba_cache)."""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap
import time
from pathlib import Path

ROOT = Path(__file__).parents[2]

# A kernel long enough that two processes' compiles of it overlap when they start together.
KERNEL = "import numba\n\n@numba.njit(cache=True)\ndef busy(x):\n    s = 0.0\n" + "".join(
    f"    if x > {i}:\n        s += x * {i} - {i % 7}\n    else:\n        s -= {i}\n" for i in range(40)) + "    return s\n"

# Each process waits for the start file, then calls the kernel and says whether it compiled.
CALLER = textwrap.dedent("""
    import json, os, sys, time
    sys.path.insert(0, sys.argv[1])
    if sys.argv[3] == "safe":  # importing harness makes the cache safe; "plain" is numba alone
        import harness
    import busy_kernel
    print("ready", flush=True)
    while not os.path.exists(sys.argv[2]):
        time.sleep(0.01)
    busy_kernel.busy(3.0)
    stats = busy_kernel.busy.stats
    print(json.dumps({"misses": sum(stats.cache_misses.values()), "hits": sum(stats.cache_hits.values())}))
""")


def _race(tmp_path: Path, mode: str) -> list[dict[str, int]]:
    """Two processes call one new cached kernel at the same moment: each one's cache
    misses (compiles) and hits (loads)."""
    (tmp_path / "busy_kernel.py").write_text(KERNEL)
    start = tmp_path / "start"
    processes = [subprocess.Popen([sys.executable, "-c", CALLER, str(tmp_path), str(start), mode], cwd=ROOT,
                                  stdout=subprocess.PIPE, text=True) for _ in range(2)]
    for p in processes:  # both imported and waiting, so that they start together
        assert p.stdout is not None and p.stdout.readline().strip() == "ready"
    start.write_text("go")
    outputs = [p.communicate(timeout=300)[0] for p in processes]
    assert all(p.returncode == 0 for p in processes), outputs
    return [json.loads(out.strip().splitlines()[-1]) for out in outputs]


def test_two_processes_compile_a_new_kernel_once(tmp_path):
    """With the cache made safe, one of two processes compiles the kernel and the other
    waits and loads that build: one miss in all, whichever comes first (numba alone may
    compile it in both: the race behind the crash that kept the trapezoid fill uncached)."""
    counts = _race(tmp_path, "safe")
    assert sum(c["misses"] for c in counts) == 1 and sum(c["hits"] for c in counts) == 1, counts


def test_a_process_waits_for_the_build_under_way_and_loads_it(tmp_path):
    """Deterministic: while the lock beside the kernel's index is held (here by the test,
    standing for a process compiling it), a process that calls the kernel waits; a plain
    numba process compiles and saves it meanwhile; once the lock is let go the waiting
    process loads that build (a hit, no compile). Without the lock it would have compiled
    its own at once."""
    import fcntl

    (tmp_path / "busy_kernel.py").write_text(KERNEL)
    cache = tmp_path / "__pycache__"
    cache.mkdir()
    start = tmp_path / "start"
    start.write_text("go")
    # numba's index file: <module>.<function>-<first line of its code: the decorator's>.py<version>.nbi
    index = cache / f"busy_kernel.busy-3.py{sys.version_info.major}{sys.version_info.minor}.nbi"
    with open(str(index) + ".compile.lock", "a") as held:
        fcntl.flock(held, fcntl.LOCK_EX)
        waiting = subprocess.Popen([sys.executable, "-c", CALLER, str(tmp_path), str(start), "safe"], cwd=ROOT,
                                   stdout=subprocess.PIPE, text=True)
        assert waiting.stdout is not None and waiting.stdout.readline().strip() == "ready"
        time.sleep(0.5)  # it reaches the kernel and the lock (only ordering, nothing measured)
        assert waiting.poll() is None, "the process did not wait for the lock"
        plain = subprocess.run([sys.executable, "-c", CALLER, str(tmp_path), str(start), "plain"], cwd=ROOT,
                               capture_output=True, text=True, timeout=300)
        assert json.loads(plain.stdout.strip().splitlines()[-1])["misses"] == 1
        fcntl.flock(held, fcntl.LOCK_UN)
    out = waiting.communicate(timeout=300)[0]
    assert json.loads(out.strip().splitlines()[-1]) == {"misses": 0, "hits": 1}
