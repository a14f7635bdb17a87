"""The paper's claims, recomputed: the registry, the report and its figures (``coinwall verify``)."""

from .verify import CLAIMS, run_verify

__all__ = ["CLAIMS", "run_verify"]
