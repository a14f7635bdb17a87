"""The paper's claims, recomputed: the registry, the report and its figures (``coinwall verify``)."""

from .claims import CLAIMS, REGISTRY, Claim
from .report import Report, Row
from .verify import run_verify

__all__ = ["CLAIMS", "REGISTRY", "Claim", "Report", "Row", "run_verify"]
