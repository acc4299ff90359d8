"""The core layer's Python side: the Cython bindings (``_<estimator>.pyx``), their generated files
(``_c_tables.py``, ``_<estimator>_fields.pxi``, ``_<estimator>.pyi``, ``c<estimator>.pxd``) and the glue
(``_common.py``, ``_<estimator>_glue.py``). Private: users import :mod:`fusion_altitude`."""


def _add_installed_extension_to_path() -> None:
    """Run from a source checkout (``python -m fusion_altitude`` in the repository root after a plain
    ``pip install .``), this source folder shadows the installed package and holds no compiled extension:
    add the installed copy's folder (the first other ``fusion_altitude/_core`` on ``sys.path`` with a compiled
    ``_observer``) to this package's search path, so the compiled modules load from there."""
    import importlib.machinery
    import os
    import sys

    here = os.path.realpath(os.path.dirname(__file__))
    suffixes = tuple(importlib.machinery.EXTENSION_SUFFIXES)
    if any(name.startswith("_observer.") and name.endswith(suffixes) for name in os.listdir(here)):
        return  # built in place: nothing shadows anything
    for entry in sys.path:
        candidate = os.path.realpath(os.path.join(entry or os.getcwd(), "fusion_altitude", "_core"))
        if candidate != here and os.path.isdir(candidate) and any(
                name.startswith("_observer.") and name.endswith(suffixes) for name in os.listdir(candidate)):
            __path__.append(candidate)  # type: ignore[name-defined]  # noqa: F821
            return


_add_installed_extension_to_path()
