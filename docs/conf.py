"""Sphinx configuration of the presag_opt documentation.

Build (from the repository root, with the ``docs`` extra installed)::

    python -m sphinx -W --keep-going -n -b html docs docs/_build/html          # notebooks not executed
    PRESAG_DOCS_EXECUTE=1 python -m sphinx -W --keep-going -n -b html docs docs/_build/full

What is found at build time, so that a new part of the package appears without an edit here:

- the API reference: every public module below ``presag_opt`` (``_ext/presag_api.py`` says which),
  one page each, written by autosummary from ``_templates/autosummary/module.rst``;
- the command-line reference: the live argument parser (``_ext/presag_cli.py``), every verb and option;
- the notebooks: every ``notebooks/*.ipynb``, copied into ``docs/notebooks/`` (not committed) and
  rendered by myst-nb; executed in their fast mode (``PRESAG_NOTEBOOK_MODE=fast``) when
  ``PRESAG_DOCS_EXECUTE=1``, shown without outputs otherwise;
- the notes: every markdown page at the top of ``docs/`` (``docs/*.md``) is listed in the notes
  table of contents of the front page.
"""

from __future__ import annotations

import os
import shutil
import sys
from datetime import date
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(DOCS / "_ext"))
sys.path.insert(0, str(ROOT))

import presag_api  # found through the path above

project = "presag_opt"
author = "presag_opt contributors"
copyright = f"{date.today().year}, {author}"
from presag_opt.version import VERSION as release  # noqa: E402 - the path above finds the checkout's package

version = release

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "numpydoc",
    "myst_nb",
    "presag_cli",
    "presag_xref",
    "presag_plaintext",
]

# ---- sources -------------------------------------------------------------------------------------

exclude_patterns = ["_build", "_templates", "_ext", "**.ipynb_checkpoints", "jupyter_execute"]
templates_path = ["_templates"]
source_suffix = {".rst": "restructuredtext", ".md": "myst-nb", ".ipynb": "myst-nb"}
root_doc = "index"
suppress_warnings = ["myst.header"]  # the existing notes start their sections at level 2 under a title

NOTEBOOKS = ROOT / "notebooks"
NOTEBOOK_COPIES = DOCS / "notebooks"


def _copy_notebooks() -> None:
    """Copy every notebook beside the sources (Sphinx reads only files under ``docs/``)."""
    NOTEBOOK_COPIES.mkdir(exist_ok=True)
    wanted = {path.name for path in NOTEBOOKS.glob("*.ipynb")}
    for stale in NOTEBOOK_COPIES.glob("*.ipynb"):
        if stale.name not in wanted:
            stale.unlink()
    for path in sorted(NOTEBOOKS.glob("*.ipynb")):
        target = NOTEBOOK_COPIES / path.name
        if not target.exists() or target.read_bytes() != path.read_bytes():
            shutil.copyfile(path, target)


_copy_notebooks()

OUTSIDE_LINKS = {"](../models/README.md)": "](guide/models.md)"}
"""Links of the notes (``docs/*.md``) to repository files outside ``docs/``, and the page that shows
each file (Sphinx reads only files under ``docs/``)."""


def _redirect_outside_links(app, docname: str, source: list[str]) -> None:
    if "/" not in docname:
        for old, new in OUTSIDE_LINKS.items():
            source[0] = source[0].replace(old, new)

# ---- myst and myst-nb ----------------------------------------------------------------------------

myst_enable_extensions = ["dollarmath", "deflist", "colon_fence", "substitution"]
myst_substitutions = {"version": release}  # the package version in the pages: {{ version }}
myst_heading_anchors = 3
EXECUTE = os.environ.get("PRESAG_DOCS_EXECUTE", "") == "1"
os.environ.setdefault("PRESAG_NOTEBOOK_MODE", "fast")  # the kernels inherit it
nb_execution_mode = "force" if EXECUTE else "off"
nb_execution_timeout = 900
nb_execution_raise_on_error = True
nb_execution_show_tb = True
nb_merge_streams = True

# ---- API reference -------------------------------------------------------------------------------

autosummary_generate = True
autosummary_ignore_module_all = True  # each module lists what it defines; a package links its __all__
autosummary_imported_members = False
autodoc_typehints = "none"  # the numpydoc Parameters sections carry the types and units
autodoc_member_order = "bysource"
autodoc_default_options: dict[str, object] = {}  # no "Bases: object" lines
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_attributes_as_param_list = True
numpydoc_xref_param_type = False
API_MODULES = presag_api.public_modules()
autosummary_context = {
    "submodules": {package: [m for m in API_MODULES if m.rpartition(".")[0] == package] for package in API_MODULES},
    "reexports": {m: presag_api.reexported(m) for m in API_MODULES},
    "api_members": {m: presag_api.members(m) for m in API_MODULES},
    "summaries": {m: presag_api.summary(m) for m in API_MODULES},
}

API_INDEX = """\
API reference
=============

Every public module of the package, one page each, found when the site is built: a module or
sub-package added to ``presag_opt`` appears here without an edit. A page shows the module's own
description, the classes, functions and documented constants it defines (numpydoc: every parameter
with its unit), and, for a package, the names it re-exports with a link to where they are defined.
``import presag_opt`` loads nothing heavy: the names listed on the :mod:`presag_opt` page are
imported from their modules on first use. Names with a leading underscore are private and not shown.

.. autosummary::
   :toctree: generated
   :template: autosummary/module.rst

{modules}
"""


def _write_api_index() -> None:
    """``api/index.rst``, listing the public modules found now (written only when it changes); the
    generated page of a module that no longer exists (moved or removed) is deleted, so that a checkout
    that built the site before the move builds it again without a warning."""
    folder = DOCS / "api"
    folder.mkdir(exist_ok=True)
    for page in (folder / "generated").glob("*.rst"):
        if page.stem not in API_MODULES:
            page.unlink()
    text = API_INDEX.format(modules="\n".join(f"   {m}" for m in API_MODULES))
    index = folder / "index.rst"
    if not index.exists() or index.read_text(encoding="utf-8") != text:
        index.write_text(text, encoding="utf-8")


_write_api_index()

# Nitpicky mode checks every reference into this project. The machines that build the site have no
# network access for intersphinx inventories, so references into Python, NumPy, SciPy, CasADi, cvxpy,
# xarray and matplotlib cannot resolve: they are ignored by name.
nitpick_ignore_regex = [
    (r"py:.*", (r"(np|numpy|scipy|sp|ca|casadi|cp|cvxpy|xr|xarray|mpl|matplotlib|plt|numba|h5py|dask|distributed|"
                r"argparse|collections|typing|pathlib|os|concurrent|multiprocessing|tomllib|dataclasses|enum|"
                r"types|ctypes|io|json|csv|datetime|functools|signal|subprocess|tqdm|IPython|openpyxl|SALib)(\..*)?")),
    (r"py:.*", (r"(int|float|str|bool|bytes|dict|list|tuple|set|frozenset|object|None|type|callable|Callable|"
                r"Path|Sequence|Mapping|Iterable|Iterator|Generator|Any|ndarray|Exception|ValueError|"
                r"RuntimeError|KeyboardInterrupt|TypeError)")),
]

# ---- HTML ----------------------------------------------------------------------------------------

html_theme = "pydata_sphinx_theme"
html_title = f"presag_opt {release}"
html_static_path: list[str] = []
html_theme_options = {
    "navigation_depth": 3,
    "show_toc_level": 2,
    "navbar_align": "left",
    "footer_start": ["copyright"],
    "footer_end": ["sphinx-version"],
    "secondary_sidebar_items": ["page-toc"],
}
html_context = {"default_mode": "auto"}  # without it a first visit logs "invalid theme mode" to the console
html_sidebars = {"getting_started": [], "reference/*": [], "project/*": [], "guide/physics": []}
html_show_sourcelink = False
# Every page names its icon; without one a browser asks the server for /favicon.ico, a request the
# pages never make, and a site served without that file logs a 404 on whichever page is open.
html_favicon = "_static/favicon.svg"


def setup(app) -> None:
    app.connect("source-read", _redirect_outside_links)
