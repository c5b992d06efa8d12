"""Finish one run of the issue-43 study: choose its checkpoint on the validation set
and export the chosen and the last checkpoint as NumPy policies.

    python tools/rl/study43/finish.py RUN_DIR

Runs ``tools/rl/validate_checkpoints.py`` on the run's checkpoints from the end of the
k2 ramp on, over the issue-30 validation set and the scenes of
``tools/rl/study43/validation_scenes/`` (10 seeds each from 20000 on; table in
``tools/rl/study43/validation/<run>.json``, resumed line by line when rerun), then
``srfm export-policy`` of the chosen checkpoint to ``policies/<run>`` and of the last
one to ``policies/<run>-final``. Rerunning it redoes only what is missing.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from study import FINAL, ROOT, SCENES, SRFM, STUDY, VALIDATION_SEEDS  # noqa: E402


def export(checkpoint: Path, out: Path, note: str) -> None:
    if out.with_suffix(".json").is_file():
        return
    subprocess.run([SRFM, "export-policy", str(checkpoint), str(out), "--note", note], check=True)


def main(argv: list[str]) -> int:
    if len(argv) != 1:
        print(__doc__, file=sys.stderr)
        return 2
    run = Path(argv[0]).resolve()
    table = STUDY / "validation" / f"{run.name}.json"
    table.parent.mkdir(parents=True, exist_ok=True)
    (STUDY / "policies").mkdir(parents=True, exist_ok=True)
    script = ROOT / "tools" / "rl" / "validate_checkpoints.py"
    words = [sys.executable, str(script), str(run), "--seeds", str(VALIDATION_SEEDS)]
    subprocess.run([*words, "--out", str(table), "--scenes", *SCENES], check=True, cwd=ROOT)
    best = json.loads(table.read_text())["best"]
    chosen = run / "checkpoints" / str(best["checkpoint"])
    export(
        chosen,
        STUDY / "policies" / run.name,
        f"{run.name}: {chosen.name}, chosen on the issue-43 validation set "
        "(tools/rl/study43/finish.py)",
    )
    export(
        run / "checkpoints" / FINAL,
        STUDY / "policies" / f"{run.name}-final",
        f"{run.name}: {FINAL}, the run's last checkpoint (tools/rl/study43/finish.py)",
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
