"""The package's version: the one place it is written.

``pyproject.toml`` reads it for the package metadata; ``presag_opt.__version__``, ``presag
--version``, the documentation and the keys of the form-finding cache and of the stores read it from
here.
"""

VERSION = "0.1.0"
"""The release, as ``MAJOR.MINOR.PATCH``."""
