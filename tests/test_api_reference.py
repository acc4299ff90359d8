"""The API reference (docs/conf.py, docs/index.rst, docs/api/): Sphinx builds it with warnings as errors, offline,
and it lists every public Python name and every public function, struct, enum and macro of the C headers.

The documented names are read from the built inventory (``objects.inv``), so a name counts only if Sphinx
documented it; the expected names come from the package (``__all__``) and from the headers, parsed here
independently of ``tools/c_api_reference.py``.
"""

import glob
import importlib
import os
import re
import subprocess
import sys
import zlib

import pytest

import fusion_altitude

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tools"))
import python_api_reference  # noqa: E402  (tools/, for its table of documented modules)


@pytest.fixture(scope="module")
def built_docs(tmp_path_factory):
    """Build the documentation once: (the sphinx-build process, the HTML folder)."""
    output = tmp_path_factory.mktemp("docs_html")
    process = subprocess.run(
        [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html", "-d", str(output / ".doctrees"),
         os.path.join(ROOT, "docs"), str(output)],
        cwd=ROOT, capture_output=True, text=True, timeout=900)
    return process, output


def inventory(output):
    """{(domain:role, name)} of the built objects.inv (version 2: four header lines, then zlib text)."""
    with open(output / "objects.inv", "rb") as handle:
        for _ in range(4):
            handle.readline()
        text = zlib.decompress(handle.read()).decode("utf-8")
    entries = set()
    for line in text.splitlines():
        match = re.match(r"(.+?)\s+(\S+:\S+)\s+-?\d+\s", line)
        if match:
            entries.add((match.group(2), match.group(1)))
    return entries


def documented_python_names(output):
    """Module-level names (``module.name``) of the documented public modules."""
    modules = {"fusion_altitude"} | {module for _, module, _ in python_api_reference.MODULES}
    names = set()
    for role, name in inventory(output):
        if role not in ("py:class", "py:function", "py:data", "py:exception"):
            continue
        module, _, attribute = name.rpartition(".")
        if module in modules:
            names.add(name)
    return names


def expected_python_names():
    names = {f"fusion_altitude.{name}" for name in fusion_altitude.__all__}
    for _, module_name, listed in python_api_reference.MODULES:
        module = importlib.import_module(module_name)
        names |= {f"{module_name}.{name}" for name in (listed if listed is not None else module.__all__)}
    return names


_HEADER_PATHS = sorted(glob.glob(os.path.join(ROOT, "csrc", "fusion_altitude*.h")))
_DOC_THEN_DECLARATION = re.compile(r"/\*\*(?!/)((?:(?!\*/).)*)\*/[ \t]*\n((?:(?!/\*)[^;{])*)[;{]", re.S)


def _is_internal(comment):
    """Whether a doc comment's body opens with Doxygen's @internal tag (the headers' helpers)."""
    return re.match(r"\s*@internal\b", comment) is not None


_DOC_THEN_MACRO = re.compile(r"/\*\*(?!/)((?:(?!\*/).)*)\*/[ \t]*\n#define[ \t]+(\w+)", re.S)


def public_c_macros():
    """The #define names right after a /** */ comment that does not open with Doxygen's @internal tag."""
    names = set()
    for path in _HEADER_PATHS:
        text = open(path, encoding="utf-8").read()
        names |= {name for comment, name in _DOC_THEN_MACRO.findall(text) if not _is_internal(comment)}
    return names


def public_c_declarations():
    """(functions, types) of the headers: declarations right after a /** */ comment not tagged @internal."""
    functions, types = set(), set()
    for path in _HEADER_PATHS:
        text = open(path, encoding="utf-8").read()
        for match in _DOC_THEN_DECLARATION.finditer(text):
            comment, head = match.groups()
            if _is_internal(comment) or head.lstrip().startswith("#"):
                continue
            if re.match(r"\s*typedef\s+(struct|enum)\b", head):
                types.add(re.compile(r"\}\s*(\w+)\s*;").search(text, match.end()).group(1))
                continue
            function = re.search(r"\b(FusionAltitude\w+)\s*\(", head)
            if function and "typedef" not in head:
                functions.add(function.group(1))
    return functions, types


def test_sphinx_build_with_warnings_as_errors_passes(built_docs):
    process, _ = built_docs
    assert process.returncode == 0, process.stdout + process.stderr


def test_every_docstring_parses_as_numpydoc(built_docs):
    process, _ = built_docs  # numpydoc reports an unknown section or a bad underline as a Python warning
    assert "UserWarning" not in process.stderr, process.stderr


def test_build_fetches_no_inventory_over_the_network():
    conf = open(os.path.join(ROOT, "docs", "conf.py"), encoding="utf-8").read()
    assert "sphinx.ext.intersphinx" not in conf
    assert re.search(r"^intersphinx_mapping = \{\}$", conf, re.M)


def test_python_reference_documents_every_name_of_fusion_altitude_all(built_docs):
    _, output = built_docs
    missing = {f"fusion_altitude.{name}" for name in fusion_altitude.__all__} - documented_python_names(output)
    assert not missing


def test_python_reference_documents_exactly_the_public_names_of_the_public_modules(built_docs):
    _, output = built_docs
    assert documented_python_names(output) == expected_python_names()


def test_documented_modules_include_those_the_topic_pages_import():
    imported = set()
    for path in glob.glob(os.path.join(ROOT, "docs", "*.md")):
        imported |= set(re.findall(r"^\s*from (fusion_altitude(?:\.\w+)*) import", open(path, encoding="utf-8").read(),
                                   re.M))
    documented = {"fusion_altitude"} | {module for _, module, _ in python_api_reference.MODULES}
    assert imported and imported <= documented


def test_compiled_estimators_show_their_constructor_parameters(built_docs):
    _, output = built_docs
    page = open(output / "api" / "python_estimators.html", encoding="utf-8").read()
    for name in ("AltitudeEstimator", "KalmanEstimator", "ComplementaryFilter", "AlphaBetaFusion", "InsEstimator",
                 "RocketEstimator"):
        signature = re.search(rf'id="fusion_altitude\.{name}">(.*?)</dt>', page, re.S).group(1)
        assert "settings" in re.sub(r"<[^>]+>", "", signature), name


def test_c_reference_documents_every_public_function_of_the_headers(built_docs):
    _, output = built_docs
    functions, _ = public_c_declarations()
    documented = {name for role, name in inventory(output) if role == "c:function"}
    assert functions and documented == functions


def test_c_reference_documents_every_public_struct_and_enum_of_the_headers(built_docs):
    _, output = built_docs
    _, types = public_c_declarations()
    documented = {name for role, name in inventory(output) if role in ("c:struct", "c:enum")}
    assert types and documented == types


def test_c_reference_documents_every_public_macro_of_the_headers(built_docs):
    _, output = built_docs
    documented = {name for role, name in inventory(output) if role == "c:macro"}
    assert documented == public_c_macros()
    assert "FUSION_ALTITUDE_GRAVITY" in documented


def test_c_reference_leaves_out_the_functions_the_headers_tag_internal(built_docs):
    _, output = built_docs
    documented = {name for role, name in inventory(output) if role == "c:function"}
    assert "FusionAltitudeKalmanPredict" not in documented  # "/** @internal" over a multi-line comment
    assert "FusionAltitudeKalmanNoSample" not in documented  # "/** @internal Marks a sensor ..." on one line
    assert "FusionAltitudeKalmanUpdate" in documented


def test_c_reference_and_sized_harnesses_agree_on_each_estimators_public_functions():
    import c_api_reference  # tools/
    import make_harnesses  # tools/
    for name, (header, prefix, *_) in make_harnesses.estimator_modules().items():
        text = open(os.path.join(ROOT, "csrc", header), encoding="utf-8").read()
        documented = [f for f in c_api_reference.public_functions(text) if f.startswith(prefix)]
        sized = [f for _, f, _ in make_harnesses.public_functions(name)]
        assert documented == sized, (name, set(documented) ^ set(sized))


@pytest.mark.parametrize("tool", ["c_api_reference.py", "python_api_reference.py"])
def test_generated_reference_pages_are_current(tool):
    process = subprocess.run([sys.executable, os.path.join(ROOT, "tools", tool), "--check"], cwd=ROOT,
                             capture_output=True, text=True, timeout=300)
    assert process.returncode == 0, process.stdout + process.stderr
