"""The module paths from before the package had layer folders, kept importable: ``fusion_altitude.scenarios``
is :mod:`fusion_altitude.sim.scenarios`, ``fusion_altitude._observer`` is ``fusion_altitude._core._observer``
(old pickles name it), and so on. An old name is the very module object of the new one (not a copy), loaded only
when imported."""

import importlib
import importlib.abc
import importlib.util
import sys
import warnings

_CORE = ("_alphabeta", "_alphabeta_glue", "_c_tables", "_common", "_complementary", "_complementary_glue", "_estimator",
         "_ins", "_ins_glue", "_kalman", "_kalman_glue", "_observer", "_observer_glue",
         "_rocket", "_rocket_glue", "_sweep", "_sweep_glue")

#: old module name → the module it now is.
MOVED_MODULES = {
    **{f"fusion_altitude.{name}": f"fusion_altitude._core.{name}" for name in _CORE},
    **{f"fusion_altitude.{name}": f"fusion_altitude.sim.{name}" for name in ("imu_sim", "rocket_sim", "scenarios")},
    "fusion_altitude.fleet_cli": "fusion_altitude.cli.fleet",
}

#: The rocket estimator's former stem ``flight`` (issue 22, item 5), for one release more: old name → the module it
#: now is. Each is the very module object of its new name (old pickles load), and importing it warns.
DEPRECATED_MODULES = {
    "fusion_altitude.reference.flight": "fusion_altitude.reference.rocket",
    "fusion_altitude._core._flight": "fusion_altitude._core._rocket",
    "fusion_altitude._core._flight_glue": "fusion_altitude._core._rocket_glue",
    "fusion_altitude._flight": "fusion_altitude._core._rocket",
    "fusion_altitude._flight_glue": "fusion_altitude._core._rocket_glue",
}
MOVED_MODULES.update(DEPRECATED_MODULES)

#: old ``python -m`` names → the module of the same package that now does that job (runpy runs its code).
RUN_AS = {"fusion_altitude.rocket_sim": "fusion_altitude.rocket_study"}


def _warn_deprecated(name: str) -> None:
    """A ``DeprecationWarning`` for importing ``name`` (:data:`DEPRECATED_MODULES`), attributed to the importing
    code: the first frame outside the import machinery and this module. (``warnings`` itself does not count the
    frames of ``importlib._bootstrap``: neither does the stack level.)"""
    def bootstrap(code):
        return "importlib" in code.co_filename and "_bootstrap" in code.co_filename

    frame, stacklevel = sys._getframe(0), 1
    while frame is not None and (bootstrap(frame.f_code)
                                 or frame.f_code.co_filename in (__file__, importlib.__file__)):
        frame = frame.f_back
        stacklevel += frame is not None and not bootstrap(frame.f_code)
    warnings.warn(f"{name} is deprecated and goes in the next release: import {DEPRECATED_MODULES[name]} (the "
                  "rocket estimator's stem is 'rocket')", DeprecationWarning, stacklevel=stacklevel)


class _AliasLoader(importlib.abc.InspectLoader):
    """Loads an old name as the module it moved to."""

    def get_code(self, fullname):
        """``python -m OLD_NAME``: the code of the module that now does the job (:data:`RUN_AS`)."""
        if fullname not in RUN_AS:
            raise ImportError(f"python -m {fullname} has moved: run python -m {MOVED_MODULES[fullname]}")
        target = importlib.util.find_spec(RUN_AS[fullname])
        return target.loader.get_code(RUN_AS[fullname])

    def get_source(self, fullname):
        return None

    def create_module(self, spec):
        if spec.name in DEPRECATED_MODULES:
            _warn_deprecated(spec.name)
        module = importlib.import_module(MOVED_MODULES[spec.name])
        self._spec = module.__spec__  # the import system sets __spec__ to the alias's; exec_module puts it back
        return module

    def exec_module(self, module):
        module.__spec__ = self._spec  # already executed under its new name; keep __spec__.parent == __package__


class _AliasFinder(importlib.abc.MetaPathFinder):
    """Finds the old names of :data:`MOVED_MODULES` (and only those)."""

    def find_spec(self, fullname, path=None, target=None):
        if fullname not in MOVED_MODULES:
            return None
        return importlib.util.spec_from_loader(fullname, _AliasLoader())


def install() -> None:
    """Put the finder on ``sys.meta_path`` once."""
    if not any(isinstance(finder, _AliasFinder) for finder in sys.meta_path):
        sys.meta_path.append(_AliasFinder())
