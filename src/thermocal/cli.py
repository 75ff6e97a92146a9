"""The ``thermocal`` command line.

Each subcommand lives in its own module under :mod:`thermocal.commands` and registers
itself on :data:`app`; heavy imports happen inside the command bodies so that
``thermocal --help`` stays fast.
"""

from __future__ import annotations

import importlib
import logging
from typing import Annotated

import typer

app = typer.Typer(
    name="thermocal",
    help=(
        "Calibrated thermal models of buildings from cheap measurements.\n\n"
        "Grey-box RC estimation (fit), detailed multi-zone simulation (simulate), "
        "retrofit analysis with the fifth-order RC method (retrofit), a built-in "
        "demonstration (demo), heat-balance identification by per-zone control (identify) "
        "and envelope calibration campaigns (calibrate)."
    ),
    no_args_is_help=True,
    add_completion=True,
    pretty_exceptions_show_locals=False,
    context_settings={"help_option_names": ["-h", "--help"]},
)

#: Log levels of ``-q`` (quiet), the default, ``-v`` and ``-vv``.
_LEVELS = (logging.ERROR, logging.WARNING, logging.INFO, logging.DEBUG)


def configure_logging(verbosity: int) -> None:
    """Send the ``thermocal`` loggers to stderr at the level of ``-q`` / ``-v`` / ``-vv``.

    Parameters
    ----------
    verbosity : int
        -1 quiet (errors only), 0 warnings (default), 1 info, 2 or more debug.
    """
    level = _LEVELS[max(0, min(verbosity + 1, len(_LEVELS) - 1))]
    logger = logging.getLogger("thermocal")
    for handler in list(logger.handlers):
        if getattr(handler, "_thermocal_cli", False):
            logger.removeHandler(handler)
    import sys

    handler = logging.StreamHandler(sys.stderr)
    handler.setFormatter(logging.Formatter("%(levelname)s: %(message)s"))
    handler._thermocal_cli = True  # type: ignore[attr-defined]
    logger.addHandler(handler)
    logger.setLevel(level)


def _print_version(value: bool) -> None:
    if value:
        from thermocal import __version__

        typer.echo(f"thermocal {__version__}")
        raise typer.Exit()


#: Subcommand modules, in the order they appear in ``--help``.
COMMAND_MODULES = ("demo", "fit", "simulate", "retrofit", "identify", "calibrate")


def _register_commands() -> None:
    for name in COMMAND_MODULES:
        try:
            importlib.import_module(f"thermocal.commands.{name}")
        except ModuleNotFoundError as exc:  # a command module not written yet
            if exc.name != f"thermocal.commands.{name}":
                raise


@app.callback()
def _root(
    version: Annotated[
        bool,
        typer.Option(
            "--version",
            "-V",
            callback=_print_version,
            is_eager=True,
            help="Print the version and exit.",
        ),
    ] = False,
    verbose: Annotated[
        int,
        typer.Option("--verbose", "-v", count=True, help="More messages on stderr (-vv: debug)."),
    ] = 0,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="Only errors on stderr.")] = False,
) -> None:
    """Calibrated thermal models of buildings from cheap measurements."""
    configure_logging(-1 if quiet else verbose)


@app.command()
def version() -> None:
    """Print the thermocal version."""
    from thermocal import __version__

    typer.echo(__version__)


_register_commands()


def main() -> None:
    """Entry point of the ``thermocal`` console script.

    Input errors (:class:`thermocal.errors.ThermocalInputError`) are printed as one clear
    message, without a traceback, and exit with status 2.
    """
    from thermocal.errors import ThermocalInputError

    try:
        app()
    except ThermocalInputError as exc:
        typer.secho(f"error: {exc}", err=True, fg=typer.colors.RED)
        raise SystemExit(2) from None


if __name__ == "__main__":
    main()
