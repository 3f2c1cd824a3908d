"""Fixtures shared by test modules in more than one folder (helpers that are not fixtures are
in :mod:`tests.support`). A module opts in with ``pytestmark =
pytest.mark.usefixtures(NAME)``; nothing here is autouse."""

import pytest

from tests.support.registries import restored_registries


@pytest.fixture
def registries_restored():
    """The test runs inside :func:`~tests.support.registries.restored_registries`: nothing it
    registers (a body, a task, an env id, a learner) reaches another test."""
    with restored_registries():
        yield
