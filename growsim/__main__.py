"""``python -m growsim`` is the ``growsim`` command."""

from growsim.cli import command

command()
