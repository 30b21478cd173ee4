import os
import pathlib

import pytest

SOURCE = pathlib.Path(os.environ.get("PROSTATESIM_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))


@pytest.fixture(scope="session")
def biopsy_path():
    return str(SOURCE / "config" / "biopsy.yaml")


@pytest.fixture
def biopsy(biopsy_path):
    import prostatesim
    return prostatesim.Scene(biopsy_path)
