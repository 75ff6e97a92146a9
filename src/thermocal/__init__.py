"""thermocal: calibrated thermal models of buildings from cheap measurements."""

__version__ = "0.1.0"
