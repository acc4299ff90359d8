"""The core layer's Python side: the Cython bindings (``_<estimator>.pyx``), their generated files
(``_c_tables.py``, ``_<estimator>_fields.pxi``, ``_<estimator>.pyi``, ``c<estimator>.pxd``) and the glue
(``_common.py``, ``_<estimator>_glue.py``). Private: users import :mod:`fusion_altitude`.

A binding converts and checks Python arguments, calls the C functions and raises for the statuses they return; it
holds no copy of the algorithm. Its settings class is the reference's (``fusion_altitude.reference.<estimator>``),
converted to the C struct. What every binding has in the same form is generated from its header into
``_<estimator>_fields.pxi``, which it includes first: its imports (the C declarations, the ``Estimator`` base, the
glue, the settings class), the enums, the settings and state conversions, the getters, ``_get_state``/``_set_state``,
``_restore``, ``c_settings_check`` (registered in the glue's ``C_SETTINGS_FUNCTIONS`` for the settings class), the
plain ``settings`` property (Kalman, complementary, INS) and the class docstring. The binding writes by hand only
what is its own: ``update``, ``update_batch``, ``reset``, the C loop of a batch and any other ``settings`` form."""


def installed_extension_folder(init_file: str, subpackage: str, module: str):
    """Run from a source checkout (``python -m fusion_altitude`` in the repository root after a plain
    ``pip install .``), the source folder of ``fusion_altitude.<subpackage>`` shadows the installed package and
    holds no compiled extension: the installed copy's folder (the first other ``fusion_altitude/<subpackage>``
    on ``sys.path`` with a compiled ``module``), to add to the package's ``__path__`` so that the compiled
    modules load from there; None when built in place or not installed."""
    import importlib.machinery
    import os
    import sys

    here = os.path.realpath(os.path.dirname(init_file))
    suffixes = tuple(importlib.machinery.EXTENSION_SUFFIXES)

    def compiled(folder):
        return any(name.startswith(module + ".") and name.endswith(suffixes) for name in os.listdir(folder))

    if compiled(here):
        return None  # built in place: nothing shadows anything
    for entry in sys.path:
        candidate = os.path.realpath(os.path.join(entry or os.getcwd(), "fusion_altitude", subpackage))
        if candidate != here and os.path.isdir(candidate) and compiled(candidate):
            return candidate
    return None


_installed = installed_extension_folder(__file__, "_core", "_observer")
if _installed is not None:
    __path__.append(_installed)  # type: ignore[name-defined]  # noqa: F821
