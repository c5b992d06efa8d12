"""What the first install of the quick start costs: wall time and ``.venv`` size of the
Makefile's two install steps, each into a new virtual environment with pip's cache off
(packages from the index, as on a fresh machine).

    python tools/bench/bench_install.py --json docs/results/performance/install.json

Runs ``make VENV=<new dir> <stamp>`` for ``run`` (what ``make benchmark`` installs: srfm
without extras) and ``dev`` (what ``make test`` installs: every extra), so the steps are
the Makefile's own. The JSON records each step's seconds and bytes, the run record of
``tools/results/record.py`` (command, commit, date, load) and the Python and pip
versions; the README's install table is generated from it (``make docs-tables``).
The figures are this machine's, on its network and with its
pip configuration (recorded: e.g. a local ``find-links`` folder of wheels), that day.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from tools.results.record import machine, run_record, start

ROOT = Path(__file__).resolve().parents[2]
STAMPS = {"run": ".installed-run", "dev": ".installed-dev"}


def folder_bytes(path: Path) -> int:
    """The bytes of every regular file under ``path`` (symlinks not followed)."""
    return sum(p.lstat().st_size for p in path.rglob("*") if p.is_file() and not p.is_symlink())


def install(step: str, workdir: Path) -> dict[str, object]:
    """Run the Makefile's install ``step`` into a new venv under ``workdir``."""
    venv = workdir / f"venv-{step}"
    env = {**os.environ, "PIP_NO_CACHE_DIR": "1"}
    t0 = time.monotonic()
    subprocess.run(
        ["make", "-C", str(ROOT), f"VENV={venv}", str(venv / STAMPS[step])],
        check=True,
        env=env,
        stdout=subprocess.DEVNULL,
    )
    seconds = time.monotonic() - t0
    pip = subprocess.run(
        [str(venv / "bin/python"), "-m", "pip", "--version"],
        check=True,
        capture_output=True,
        text=True,
    ).stdout.split()[1]
    return {
        "step": step,
        "seconds": round(seconds, 1),
        "venv_bytes": folder_bytes(venv),
        "load_after": round(os.getloadavg()[0], 2),
        "pip": pip,
    }


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--json", type=Path, required=True, help="where to write the figures")
    ap.add_argument("--steps", nargs="+", choices=sorted(STAMPS), default=["run", "dev"])
    args = ap.parse_args(argv)
    started, t0, load = start()
    with tempfile.TemporaryDirectory(prefix="srfm-install-") as tmp:
        rows = []
        for step in args.steps:
            row = install(step, Path(tmp))
            print(f"{step}: {row['seconds']} s, {int(row['venv_bytes']) / 1e9:.2f} GB", flush=True)
            rows.append(row)
    pip_config = subprocess.run(
        [sys.executable, "-m", "pip", "config", "list"], capture_output=True, text=True
    ).stdout.splitlines()
    payload = {
        "python": sys.version.split()[0],
        "pip_config": pip_config,
        "steps": rows,
        "run": run_record(started, t0, load),
        "machine": machine(),
    }
    tmp_path = args.json.with_suffix(".json.tmp")
    tmp_path.write_text(json.dumps(payload, indent=1) + "\n", encoding="utf-8")
    tmp_path.replace(args.json)


if __name__ == "__main__":
    main()
