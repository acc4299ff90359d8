"""The reference settings docstrings list every setting of the C struct, with the header's default.

The header (``csrc/fusion_altitude*.h``) is the single source of the settings: their names, order and
defaults reach Python through the generated ``fusion_altitude/_c_tables.py``. The settings classes'
docstrings are written by hand (they explain each setting); these tests hold them to the header, so that a
new setting or a changed default fails here until the docstring says it.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

from fusion_altitude import _c_tables
from fusion_altitude.reference import complementary, rocket, ins, kalman, observer

#: settings class → the generated table of its C struct (python name first, default fourth; a nested struct's
#: default, a tuple, is not compared).
FLAT = {
    "KalmanSettings": (kalman.KalmanSettings, _c_tables.KALMAN_SETTINGS),
    "ComplementarySettings": (complementary.ComplementarySettings, _c_tables.COMPLEMENTARY_SETTINGS),
    "InsSettings": (ins.InsSettings, _c_tables.INS_SETTINGS),
    "AltitudeSettings": (observer.AltitudeSettings, _c_tables.OBSERVER_SETTINGS),
    "RocketSettings": (rocket.RocketSettings, _c_tables.ROCKET_SETTINGS),
}

_ENTRY = re.compile(r"^    (\w+(?:, \w+)*) : (.*)$")
_NUMBER = re.compile(r"^[-+]?(?:\d+\.?\d*(?:e[-+]?\d+)?|inf|True|False)", re.I)
_DEFAULT = re.compile(r"\bdefault ([-+]?(?:\d+\.?\d*(?:e[-+]?\d+)?|inf|True|False))", re.I)


def documented_defaults(settings_class) -> dict:
    """{name: the default the docstring writes (its text), or None} from the Parameters section."""
    entries = {}
    for line in (settings_class.__doc__ or "").splitlines():
        match = _ENTRY.match(line)
        if not match:
            continue
        names = match.group(1).split(", ")
        default = _DEFAULT.search(match.group(2))
        if default is not None and len(names) == 1:  # "name : float, default 2.40"
            entries[names[0]] = default.group(1)
            continue
        values = match.group(2).split(", ")
        for i, name in enumerate(names):
            value = _NUMBER.match(values[i].strip()) if len(values) == len(names) else None
            entries[name] = value.group(0) if value else None
    return entries


def _same_default(written: str, default) -> bool:
    if written in ("True", "False"):
        return (written == "True") == bool(default)
    return bool(np.float32(float(written)) == np.float32(default))


@pytest.mark.parametrize("name", sorted(FLAT))
def test_settings_docstring_names_every_field_of_the_c_struct(name):
    settings_class, table = FLAT[name]
    documented = documented_defaults(settings_class)
    missing = [row[0] for row in table if row[0] not in documented]
    assert not missing, f"{name}'s docstring lacks {missing} (see the header's settings struct)"


@pytest.mark.parametrize("name", sorted(FLAT))
def test_settings_docstring_names_no_field_the_c_struct_lacks(name):
    settings_class, table = FLAT[name]
    extra = sorted(set(documented_defaults(settings_class)) - {row[0] for row in table})
    assert not extra, f"{name}'s docstring names {extra}, which the header's settings struct does not have"


@pytest.mark.parametrize("name", sorted(FLAT))
def test_settings_docstring_defaults_are_the_headers(name):
    settings_class, table = FLAT[name]
    documented = documented_defaults(settings_class)
    wrong = {row[0]: (documented[row[0]], row[3]) for row in table
             if documented.get(row[0]) is not None and not isinstance(row[3], tuple)
             and not _same_default(documented[row[0]], row[3])}
    assert not wrong, f"{name}'s docstring defaults differ from SettingsDefault() (written, C): {wrong}"
