"""Your own scenario file: walls, a door, a group and people entering at a rate.

    python examples/02_own_scenario.py          # simulate, write logs, print how to look
    python examples/02_own_scenario.py --fast   # the same (one episode is fast anyway)

examples/lobby.toml is a scenario in srfm's schema (docs/scenarios.md): a wall with a
door, two walkers, a group of three entering at 4 s, a standing person and a stream of
people entering at 0.25 per second. The script checks it, simulates one twin episode,
writes its Rerun recording (.rrd) and MCAP log, and prints the command that opens the
recording in the Rerun viewer.
"""

import os
import sys
from pathlib import Path

import srfm
from srfm.logs import write_episode_mcap, write_rrd
from srfm.metrics import episode_metrics

FAST = "--fast" in sys.argv or os.environ.get("SRFM_EXAMPLES_FAST") == "1"
OUT = Path(os.environ.get("SRFM_EXAMPLES_OUT", "out/examples")) / "02_own_scenario"

# Loading validates the file: a mistake is a ScenarioError naming the key and the value.
scenario = srfm.load_scenario(Path(__file__).with_name("lobby.toml"))
setup = srfm.episode_setup(scenario, seed=0)  # the pedestrians of seed 0, before the run
print(f"{scenario.name}: {scenario.description}")
print(f"  {setup.crowd.n} pedestrians in all, world {scenario.world}")

# The global router plans every pedestrian's and the robot's way round the wall and
# through the door; the DWA planner follows the robot's waypoints.
record = srfm.run_episode(scenario, seed=0, planner="dwa")
entered = record.present()[-1].sum()  # people there at the end (arrivals included)
print(f"  robot: {record.outcome} at step {record.end_step} of {record.horizon_steps}")
print(
    f"  {entered} pedestrians there at the end; largest deviation caused by the robot "
    f"{record.twin_separation_m().max():.2f} m"
)

OUT.mkdir(parents=True, exist_ok=True)
metrics = episode_metrics(record)
rrd = OUT / "lobby-seed0.rrd"
write_rrd(rrd, record, scenario=scenario, metrics=metrics, forces=not FAST)
write_episode_mcap(OUT / "lobby-seed0.mcap", record, scenario=scenario, metrics=metrics)
print(f"  Fréchet deviation {metrics.values['frechet_m']:.2f} m; logs in {OUT}")
print(f"open the recording:  srfm view {rrd}   (or: python -m rerun {rrd})")
print(
    f"the same from the command line:  srfm simulate --scenario {scenario.source} "
    "--seed 0 --planner dwa --out run"
)
