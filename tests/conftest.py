"""Shared test fixtures, and the settings that keep the suite independent of the machine's speed."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest
from hypothesis import HealthCheck, settings

REPO = Path(__file__).resolve().parents[1]
SHARED_DATA = REPO.parent / "shared" / "data"

#: programs from the system that some tests run (the README's quick start installs them)
SYSTEM_TOOLS = {"ffmpeg": ("ffmpeg",), "chromium": ("chromium", "chromium-browser", "google-chrome"),
                "C++ compiler": ("c++", "g++", "clang++"), "cmake": ("cmake",), "exiftool": ("exiftool",)}

# Hypothesis times each example (a 200 ms deadline, and health checks that stop "too slow" data
# generation): on a busy machine those fail tests that are right. The suite tests values, never speed.
settings.register_profile("lenslab", deadline=None, suppress_health_check=[HealthCheck.too_slow])
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "lenslab"))


def pytest_report_header(config) -> list[str]:
    found = []
    for name, commands in SYSTEM_TOOLS.items():
        path = next((p for p in map(shutil.which, commands) if p), None)
        found.append(f"{name} {path}" if path else f"{name} MISSING")
    return ["system tools: " + ", ".join(found)]


@pytest.fixture(scope="session")
def shared_data() -> Path:
    """``../shared/data`` (real HDR panoramas and tricky format files); skips where absent."""
    if not SHARED_DATA.is_dir():
        pytest.skip("../shared/data is not present on this machine")
    return SHARED_DATA
