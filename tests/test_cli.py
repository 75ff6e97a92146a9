"""The command line: help text and the version command."""

from typer.testing import CliRunner

from thermocal import __version__
from thermocal.cli import app


def test_help_lists_version_command():
    result = CliRunner().invoke(app, ["--help"])
    assert result.exit_code == 0
    assert "version" in result.output


def test_version():
    result = CliRunner().invoke(app, ["version"])
    assert result.exit_code == 0
    assert result.output.strip() == __version__
