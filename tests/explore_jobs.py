"""The explorer's jobs for the tests (a worker's child imports this module by name): the server's own, and one
that fails as a bug would, whose message must still reach the page."""

from coinwall.cases.explore.compute import JOBS as SERVER_JOBS


def crash(spec: dict) -> dict:
    raise ZeroDivisionError("a deliberate bug for the tests")


JOBS = {**SERVER_JOBS, "crash": crash}
