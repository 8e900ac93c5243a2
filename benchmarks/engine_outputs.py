"""The dynamic engines' outputs as bytes, to show that a change of the engine's code leaves every number
as it was. Run: python benchmarks/engine_outputs.py FOLDER [--compare OTHER_FOLDER]

Writes into FOLDER the standard output of ``presag simulate --json`` for

- ``case``: the case study (its ten speeds at 120 N, one batch);
- ``batch12``: a 12-run batch of the case study (60, 90, 120, 150 km/h × 80, 100, 120 N);
- ``single``: one run of the case study (80 km/h, 100 N: the single-run engine);

each with the compiled C sweeps (``compiled``) and with ``PRESAG_NO_COMPILE=1`` (``numba``: the numba
kernel and no C code anywhere). The one thing that differs from run to run, the wall time
(``"wall_time_s"``), is written as 0; every other byte is the command's. Every command runs as its own process with a cache folder of this
run (``XDG_CACHE_HOME``), so the form-finding is the same on both trees. With ``--compare`` the files
are compared byte by byte with those of another folder (written by this script on another tree); the
exit status is 1 if any differs.
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

CASES = {
    "case": ["--case", "case_study_st98"],
    "batch12": ["--case", "case_study_st98", "--speed", "60,90,120,150", "--static-force", "80,100,120"],
    "single": ["--case", "case_study_st98", "--speed", "80", "--static-force", "100"],
}
BACKENDS = {"compiled": {}, "numba": {"PRESAG_NO_COMPILE": "1"}}
WALL_TIME = re.compile(rb'"wall_time_s": [-+.0-9eE]+')


def without_wall_time(output: bytes) -> bytes:
    """The command's output with every wall time [s] written as 0."""
    return WALL_TIME.sub(b'"wall_time_s": 0', output)


def dump(folder: Path) -> None:
    """Write one file per case and back-end into ``folder``."""
    folder.mkdir(parents=True, exist_ok=True)
    presag = Path(sys.executable).with_name("presag")
    with tempfile.TemporaryDirectory(prefix="engine_outputs_") as cache:
        for backend, extra in BACKENDS.items():
            for name, argv in CASES.items():
                env = {**os.environ, "XDG_CACHE_HOME": cache, **extra}
                done = subprocess.run([str(presag), "simulate", *argv, "--json"], env=env, capture_output=True,
                                      check=True)
                (folder / f"{name}_{backend}.json").write_bytes(without_wall_time(done.stdout))
                print(f"{name} ({backend}): {len(done.stdout)} bytes", flush=True)


def compare(folder: Path, other: Path) -> int:
    """Print, per file, whether it is byte-identical in both folders; the number that differ."""
    differ = 0
    for path in sorted(other.glob("*.json")):
        same = (folder / path.name).read_bytes() == path.read_bytes()
        differ += not same
        print(f"{path.name}: {'identical' if same else 'DIFFERS'}")
    return differ


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", type=Path, help="folder to write the outputs into")
    parser.add_argument("--compare", type=Path, default=None, help="folder of outputs to compare with")
    args = parser.parse_args()
    dump(args.folder)
    return 1 if args.compare is not None and compare(args.folder, args.compare) else 0


if __name__ == "__main__":
    sys.exit(main())
