"""``python -m thermocal``: the same command line as the ``thermocal`` script."""

from thermocal.cli import run

if __name__ == "__main__":
    run()
