"""The ``thermocal`` command line.

Each subcommand lives in its own module under :mod:`thermocal.commands` and registers
itself on :data:`app`; heavy imports happen inside the command bodies so that
``thermocal --help`` stays fast.
"""

from __future__ import annotations

import importlib

import typer

app = typer.Typer(
    name="thermocal",
    help=(
        "Calibrated thermal models of buildings from cheap measurements.\n\n"
        "Grey-box RC estimation (fit), detailed multi-zone simulation (simulate), "
        "retrofit analysis of paper 000 (retrofit) and a built-in demonstration (demo)."
    ),
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_show_locals=False,
)

#: Subcommand modules, in the order they appear in ``--help``.
COMMAND_MODULES = ("demo", "fit", "simulate", "retrofit")


def _register_commands() -> None:
    for name in COMMAND_MODULES:
        try:
            importlib.import_module(f"thermocal.commands.{name}")
        except ModuleNotFoundError as exc:  # a command module not written yet
            if exc.name != f"thermocal.commands.{name}":
                raise


@app.callback()
def _root() -> None:
    """Calibrated thermal models of buildings from cheap measurements."""


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
