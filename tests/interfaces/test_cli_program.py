"""The command tree: a group given no command prints its help (it printed nothing)."""

import pytest

from mimics.interfaces.cli.program import main


@pytest.mark.parametrize(("argv", "lines"), [
    ([], ["Usage: mimics [OPTIONS] COMMAND", "run", "battery", "list"]),
    (["list"], ["Usage: mimics list [OPTIONS] COMMAND", "algorithms", "scenarios", "robots"]),
    (["battery"], ["Usage: mimics battery [OPTIONS] COMMAND", "run", "report"]),
])
def test_a_group_without_a_command_prints_its_help(capsys, argv: list[str],
                                                   lines: list[str]) -> None:
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert out.startswith(lines[0])
    commands = out.split("Commands:", 1)[1].split()
    for name in lines[1:]:
        assert name in commands, (name, out)
