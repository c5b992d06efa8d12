"""Planners in other processes and other languages: the C++ client and the Python client
of the external planner protocol, benchmarked beside srfm's own planners.

    python examples/07_external_planner.py          # paper suite, seeds 0-2, figures
    python examples/07_external_planner.py --fast   # crosswalk and circle, seed 0

The C++ client in clients/cpp is built with CMake (it needs Debian's libmsgpack-cxx-dev,
which `make setup` installs). Its straight planner gives exactly the record of srfm's
built-in ``straight``; its reactive planner avoids people. The Python planner below is
a plain function served by ``srfm.planners.external.serve`` in a process of its own.
The same from the command line:

    srfm benchmark -p straight,external:cpp --external cpp=build/cpp/straight_planner

See docs/planners-any-language.md: the protocol, the C++ walk-through, the failures.
"""

import os
import subprocess
import sys
from pathlib import Path

from srfm.benchmark import BenchmarkRequest, run_benchmark
from srfm.planners.external import define_external

FAST = "--fast" in sys.argv or os.environ.get("SRFM_EXAMPLES_FAST") == "1"
OUT = Path(os.environ.get("SRFM_EXAMPLES_OUT", "out/examples")) / "07_external_planner"
CLIENT = Path(__file__).resolve().parents[1] / "clients" / "cpp"

# A planner in Python, run as its own process: any function of (step, episode).
PYTHON_PLANNER = '''
import math
from srfm.planners.external import serve

def act(step, episode):
    """Turn to the goal, then drive; half speed when someone is within 1.5 m."""
    error = math.remainder(
        math.atan2(step.goal[1] - step.y, step.goal[0] - step.x) - step.theta, 2 * math.pi
    )
    near = any(math.dist((step.x, step.y), p) < 1.5 for p in step.ped_pos)
    v = episode.max_speed_mps * max(math.cos(error), 0.0) * (0.5 if near else 1.0)
    w = max(-episode.max_angular_speed_radps, min(episode.max_angular_speed_radps, 2 * error))
    return v, w

serve(act, detection_range_m=3.0)
'''

if __name__ == "__main__":
    build = OUT / "cpp-build"
    subprocess.run(
        ["cmake", "-S", str(CLIENT), "-B", str(build)], check=True, stdout=subprocess.DEVNULL
    )
    subprocess.run(
        ["cmake", "--build", str(build), "-j", "2"], check=True, stdout=subprocess.DEVNULL
    )
    script = OUT / "python_planner.py"
    script.write_text(PYTHON_PLANNER, encoding="utf-8")

    # Each definition names a program; "external:NAME" runs it like any planner.
    planners = [
        "straight",
        define_external("cpp", [str(build / "straight_planner")]),
        define_external("reactive", [str(build / "reactive_planner")]),
        define_external("py", [sys.executable, str(script)]),
    ]
    request = BenchmarkRequest.create(
        scenarios=["crosswalk", "circle"] if FAST else None,
        planners=planners,
        seeds=[0] if FAST else None,
        quick=True,
    )
    summary = run_benchmark(request, OUT / "results", jobs=2, figures=not FAST, force=True)
    print((OUT / "results" / "table.md").read_text(encoding="utf-8"))
    page = OUT / "results" / "report.html"
    print(f"{summary.simulated} episodes in {summary.wall_time_s:.1f} s; open {page}")
