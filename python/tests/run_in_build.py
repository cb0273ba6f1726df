"""Runs this pytest suite against the package of a meson build directory
(the test python_pytest of tests/meson.build, suite `python`).

    python3 run_in_build.py JUNIT_XML EXTENSION PACKAGE_SOURCE...

The build leaves the extension (_hpfc*.so) in BUILD/python/ and the
package's .py files in the source tree, so nothing there imports as
`hpfc`. This lays the two out as the install does, as links in a temporary
hpfc/ directory, and runs pytest with that directory first on PYTHONPATH:
the tests see exactly what the build made, and a stale installed package
cannot stand in for it. The tools (HPFC_PACK, HPFC_INSPECT,
HPFC_REQUIRE_TOOLS) come from meson's environment. The pytest report goes
to JUNIT_XML, which tools/run-tests.sh counts.

Exit status: pytest's, except 77 (meson's "skipped") when this
interpreter has no pytest or numpy, and 1 when pytest collected no test
(its 5), which would otherwise pass as an empty run.
"""

import importlib.util
import os
import subprocess
import sys
import tempfile
from pathlib import Path


def main():
    junit, ext, *sources = sys.argv[1:]
    # a report of an earlier run must not be counted for this one
    Path(junit).unlink(missing_ok=True)
    for mod in ("pytest", "numpy"):
        if importlib.util.find_spec(mod) is None:
            print(f"python_pytest: skipped, {sys.executable} has no {mod}")
            return 77
    tests = Path(__file__).resolve().parent
    with tempfile.TemporaryDirectory(prefix="hpfc-pytest.") as tmp:
        pkg = Path(tmp) / "hpfc"
        pkg.mkdir()
        for src in [ext, *sources]:
            (pkg / Path(src).name).symlink_to(Path(src).resolve())
        env = dict(os.environ)
        env["PYTHONPATH"] = os.pathsep.join(
            [tmp] + ([env["PYTHONPATH"]] if env.get("PYTHONPATH") else []))
        # no __pycache__ left in the source tree (conftest.py, the tests)
        env["PYTHONDONTWRITEBYTECODE"] = "1"
        cmd = [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider",
               f"--junitxml={junit}", str(tests)]
        status = subprocess.run(cmd, env=env, check=False).returncode
    if status == 5:
        print("python_pytest: pytest collected no test")
        return 1
    return status


if __name__ == "__main__":
    sys.exit(main())
