import os
import shutil

import pytest

ROOT = os.path.normpath(os.path.join(os.path.dirname(__file__), "..", ".."))


@pytest.fixture
def root():
    """The checkout's root (scenes/, data/, tests/data/)."""
    return ROOT


@pytest.fixture
def femto_cli():
    """The `femto` tool to compare with: FEMTO_CLI, or the README's build/cli/femto."""
    path = os.environ.get("FEMTO_CLI") or os.path.join(ROOT, "build", "cli", "femto")
    if not os.access(path, os.X_OK):
        path = shutil.which("femto")
    if path is None:
        pytest.fail("no femto tool to compare with: build it (cmake --build build) or set "
                    "FEMTO_CLI")
    return path



@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    """Under CI=true a skipped test is a failure (the project's rule: a test that did not run
    did not pass)."""
    outcome = yield
    report = outcome.get_result()
    if os.environ.get("CI") == "true" and report.skipped:
        reason = report.longrepr[2] if isinstance(report.longrepr, tuple) else report.longrepr
        report.outcome = "failed"
        report.longrepr = "skipped under CI=true (every test must run): %s" % reason
