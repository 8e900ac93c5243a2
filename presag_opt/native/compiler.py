"""C libraries built on the user's machine with its C compiler, kept in the cache folder.

Two hot spots run as compiled C when a compiler is available: the static model's axial element
functions (C that CasADi generates, :mod:`presag_opt.native.casadi_elements`) and the batch simulator's
sweeps over all DOFs (:mod:`presag_opt.native.sweeps`). Both give the same numbers as their
fallbacks to the last bit; only the speed differs.

:func:`build` compiles a source text with ``$CC`` (default ``cc``) into
the runtime's library folder (:attr:`presag_opt.runtime.Runtime.library_folder`, by default
``$XDG_CACHE_HOME/presag_opt/compiled``), named by a hash of the source, the flags, the compiler
and, for code tuned to this processor (``-march=native``), the processor's model and instruction
sets, so that any change builds a new library and a cache folder shared between different machines
never hands one the other's code. A build is written atomically (concurrent processes may build the
same library). Without a working compiler, or with compiling turned off in the runtime
(:attr:`~presag_opt.runtime.Runtime.compile`; ``PRESAG_NO_COMPILE=1`` for the command line),
nothing is built and the callers use their fallbacks.
"""

from __future__ import annotations

import functools
import hashlib
import os
import platform
import shutil
import subprocess
import tempfile
from collections.abc import Sequence
from pathlib import Path

from presag_opt import runtime


def compiling_disabled() -> bool:
    """Whether the runtime in force turns compiled code off (:attr:`presag_opt.runtime.Runtime.compile`)."""
    return not runtime.current().compile


@functools.cache
def _processor() -> str:
    """The processor's model and instruction sets (what ``-march=native`` compiles for)."""
    described = platform.machine()
    try:
        lines = Path("/proc/cpuinfo").read_text().splitlines()
    except OSError:
        return described + platform.processor()
    for key in ("model name", "flags", "Features"):
        described += next((line for line in lines if line.startswith(key)), "")
    return described


def build(stem: str, source: str, flags: Sequence[str]) -> Path | None:
    """The shared library compiled from ``source`` (built if missing), or None if it cannot be built.

    Parameters
    ----------
    stem : str
        Start of the library's file name.
    source : str
        C source text.
    flags : sequence of str
        Compiler flags besides ``-fPIC -shared``.

    Returns
    -------
    Path or None
        None when compiling is turned off, no compiler is found or the build fails.
    """
    settings = runtime.current()
    if not settings.compile:
        return None
    compiler = shutil.which(os.environ.get("CC", "cc"))
    if compiler is None:
        return None
    return _build(stem, source, tuple(flags), compiler, settings.library_folder)


@functools.cache
def _build(stem: str, source: str, flags: tuple[str, ...], compiler: str, folder: Path) -> Path | None:
    """:func:`build` with ``compiler`` into ``folder``, once per process for the same arguments (the
    library's file name is a function of them, and a failed build fails again)."""
    machine = _processor() if "-march=native" in flags else platform.machine()
    key = hashlib.sha256("\0".join([source, *flags, compiler, machine]).encode()).hexdigest()[:20]
    target = folder / f"{stem}-{key}.so"
    if target.exists():
        return target
    temporary = None
    with tempfile.TemporaryDirectory() as scratch:
        path = Path(scratch) / f"{stem}.c"
        path.write_text(source)
        built = Path(scratch) / f"{stem}.so"
        try:
            subprocess.run([compiler, *flags, "-fPIC", "-shared", str(path), "-o", str(built)],
                           check=True, capture_output=True, timeout=120)
            folder.mkdir(parents=True, exist_ok=True)
            handle, temporary = tempfile.mkstemp(dir=folder, suffix=".so.tmp")
            os.close(handle)
            shutil.copyfile(built, temporary)
            os.replace(temporary, target)  # atomic: concurrent processes build the same file
        except (OSError, subprocess.SubprocessError):
            if temporary is not None and os.path.exists(temporary):
                os.unlink(temporary)
            return None
    return target
