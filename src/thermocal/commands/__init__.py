"""Command-line subcommands; each module registers its commands on ``thermocal.cli.app``."""
