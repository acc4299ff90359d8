"""Sphinx configuration of the fusion-altitude documentation: the topic pages (``docs/*.md``) and the API reference.

Build (offline, warnings are errors)::

    sphinx-build -W -b html docs build/docs

The Python reference is read from the installed (or built-in-place) package by autodoc; the C reference
(``api/c.rst``) is generated from the headers by ``python tools/c_api_reference.py``.
"""

import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)  # the checkout, built in place (python setup.py build_ext --inplace), before site-packages

import fusion_altitude  # noqa: E402

project = "fusion-altitude"
author = "fusion-altitude contributors"
copyright = "fusion-altitude contributors"
release = fusion_altitude.__version__
version = release

extensions = [
    "sphinx.ext.autodoc",
    "numpydoc",
    "myst_parser",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", "images/*.md"]

# Offline: no inventory is fetched.
intersphinx_mapping = {}

# autodoc: members in source order (the Cython classes': alphabetical); method signatures from the compiled
# bindings (Cython's binding=True); a cdef class's constructor parameters, which Python cannot inspect, are
# written into its directive by tools/python_api_reference.py from the .pyx.
autodoc_member_order = "bysource"
autodoc_default_options = {}  # each directive of docs/api/ says what it documents
autodoc_typehints = "none"  # the numpydoc "Parameters" sections carry the types and units

# numpydoc: no autosummary tables of members (autodoc documents them).
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False

# The topic pages link to the C headers (``../csrc/fusion_altitude_ins.h``), outside the documentation
# folder: they read on GitHub; here the C reference (api/c.rst) documents the headers.
nitpick_ignore_regex = [("myst", r"\.\./csrc/fusion_altitude[a-z_]*\.h")]

# MyST: the topic pages' headings get anchors (they link to one another by #heading).
myst_heading_anchors = 4

html_theme = "alabaster"
html_static_path = []


# Plain-text docstrings write absolute values as |v| (m/s), which reST reads as a substitution reference:
# show them as written. Inline literals (``...``) are left alone.
_ABSOLUTE_VALUE = re.compile(r"(?<![\\\w|`])\|(?=[^\s|])([^|`\n]*?[^\s|\\])\|(?![\w|`])")
_INLINE_LITERAL = re.compile(r"(``.+?``)")


def escape_absolute_values(app, what, name, obj, options, lines):
    """autodoc-process-docstring: ``|x|`` → ``\\|x\\|`` outside inline literals."""
    for index, line in enumerate(lines):
        parts = _INLINE_LITERAL.split(line)
        lines[index] = "".join(part if part.startswith("``") else _ABSOLUTE_VALUE.sub(r"\\|\1\\|", part)
                               for part in parts)


def setup(app):
    app.connect("autodoc-process-docstring", escape_absolute_values)
