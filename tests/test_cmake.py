"""The CMake package (CMakeLists.txt): consumers find the headers by find_package or add_subdirectory, the
pkg-config file gives their include path, and CTest runs the C unit tests of csrc/tests."""

import os
import re
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
CONSUMER = ROOT / "tests" / "cmake_consumer"


def tool(name: str) -> str:
    path = shutil.which(name)
    assert path is not None, f"{name} is not installed (.ci/run installs it)"
    return path


def run(command, **kwargs) -> subprocess.CompletedProcess:
    result = subprocess.run([str(part) for part in command], capture_output=True, text=True, timeout=600, **kwargs)
    assert result.returncode == 0, " ".join(map(str, command)) + "\n" + result.stdout + result.stderr
    return result


@pytest.fixture(scope="module")
def installed_prefix(tmp_path_factory) -> Path:
    """The repository configured without its tests and installed into a fresh prefix."""
    build = tmp_path_factory.mktemp("cmake-build")
    prefix = tmp_path_factory.mktemp("prefix")
    run([tool("cmake"), "-S", ROOT, "-B", build, "-DFUSION_ALTITUDE_BUILD_TESTS=OFF", f"-DCMAKE_INSTALL_PREFIX={prefix}"])
    run([tool("cmake"), "--build", build])
    run([tool("cmake"), "--install", build])
    return prefix


def build_consumer(source: Path, build: Path, *definitions: str) -> str:
    """Configures and builds a consumer project, runs its program and returns what it printed."""
    run([tool("cmake"), "-S", source, "-B", build, *definitions])
    run([tool("cmake"), "--build", build])
    return run([build / "consumer"]).stdout


def test_install_puts_every_header_the_package_config_and_the_pc_file_under_the_prefix(installed_prefix):
    headers = sorted(path.name for path in (ROOT / "csrc").glob("fusion_altitude*.h"))
    assert sorted(path.name for path in (installed_prefix / "include").glob("*.h")) == headers
    cmake_dir = installed_prefix / "share" / "fusion_altitude" / "cmake"
    for name in ["fusion_altitudeConfig.cmake", "fusion_altitudeConfigVersion.cmake", "fusion_altitude_targets.cmake"]:
        assert (cmake_dir / name).is_file(), name
    assert (installed_prefix / "share" / "pkgconfig" / "fusion_altitude.pc").is_file()


def test_a_consumer_builds_against_the_installed_prefix_with_find_package(installed_prefix, tmp_path):
    output = build_consumer(CONSUMER / "find_package", tmp_path, f"-DCMAKE_PREFIX_PATH={installed_prefix}")
    import fusion_altitude
    version = fusion_altitude.__version__
    assert output == f"fusion_altitude {version} ({version})\n"


def test_find_package_refuses_a_newer_minor_version_than_installed(installed_prefix, tmp_path):
    import fusion_altitude
    major, minor, _ = fusion_altitude.__version__.split(".")
    source = tmp_path / "src"
    source.mkdir()
    (source / "CMakeLists.txt").write_text(
        "cmake_minimum_required(VERSION 3.16)\nproject(too_new LANGUAGES C)\n"
        f"find_package(fusion_altitude {major}.{int(minor) + 1} CONFIG REQUIRED)\n")
    result = subprocess.run([tool("cmake"), "-S", str(source), "-B", str(tmp_path / "build"),
                             f"-DCMAKE_PREFIX_PATH={installed_prefix}"], capture_output=True, text=True)
    assert result.returncode != 0
    assert "fusion_altitude" in result.stderr


def test_a_consumer_builds_with_add_subdirectory(tmp_path):
    output = build_consumer(CONSUMER / "add_subdirectory", tmp_path, f"-DFUSION_ALTITUDE_SOURCE_DIR={ROOT}")
    assert output.startswith("fusion_altitude ")
    # a subproject neither installs nor builds its tests by default
    assert not list(tmp_path.rglob("fusion_altitude_test_*"))


def test_pkg_config_gives_the_include_path_of_the_installed_headers(installed_prefix, tmp_path):
    environment = dict(os.environ, PKG_CONFIG_PATH=str(installed_prefix / "share" / "pkgconfig"))
    cflags = run([tool("pkg-config"), "--cflags", "fusion_altitude"], env=environment).stdout.split()
    assert cflags == [f"-I{installed_prefix / 'include'}"]
    import fusion_altitude
    version = run([tool("pkg-config"), "--modversion", "fusion_altitude"], env=environment).stdout.strip()
    assert version == fusion_altitude.__version__
    run([tool("gcc"), "-std=c99", *cflags, CONSUMER / "main.c", "-o", tmp_path / "consumer", "-lm"])
    assert run([tmp_path / "consumer"]).stdout.startswith("fusion_altitude ")


@pytest.mark.slow
def test_ctest_builds_and_passes_every_c_unit_test(tmp_path):
    run([tool("cmake"), "-S", ROOT, "-B", tmp_path])
    run([tool("cmake"), "--build", tmp_path, "--parallel", "2"])
    result = run([tool("ctest"), "--test-dir", tmp_path, "--output-on-failure"])
    programs = sorted(path.stem for path in (ROOT / "csrc" / "tests").glob("test_*.c"))
    # "100% tests passed, 0 tests failed out of 7" (CMake 3) or "100% tests passed out of 7" (CMake 4)
    assert re.search(rf"^100% tests passed(, 0 tests failed)? out of {len(programs)}$", result.stdout, re.M), result.stdout
    for program in programs:
        assert f" {program} " in result.stdout, program
