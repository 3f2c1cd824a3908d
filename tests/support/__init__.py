"""Shared helpers of the test modules: what more than one test module needs lives here, in a
module named for what it holds, and no test module imports another
(``tests/test_architecture.py`` checks it)."""
