"""``mimics COMMAND ...`` builds only that command under the app's root
(``program._command``): what the user sees must be what the whole app gives."""

import pytest

from mimics.interfaces.cli import program

CASES = [
    ["run", "--help"],
    ["report", "--help"],
    ["run", "line"],  # a missing argument
    ["run", "line", "go_to_goal", "--seed", "-1"],  # refused by guard_values
    ["run", "line", "go_to_goal", "--no-such-option"],
    ["rnu"],  # no such command: the whole app answers
    ["--help"],
]


def outcome(capsys, argv: list[str]) -> tuple[int, str, str]:
    code = program.main(list(argv))
    captured = capsys.readouterr()
    return code, captured.out, captured.err


@pytest.mark.parametrize("argv", CASES, ids=" ".join)
def test_one_command_answers_as_the_whole_app(capsys, monkeypatch, argv: list[str]) -> None:
    alone = outcome(capsys, argv)
    monkeypatch.setattr(program, "_first_word", lambda args: None)  # always the whole app
    whole = outcome(capsys, argv)
    assert alone == whole
    assert alone[0] in (0, 2) and (alone[1] or alone[2])


def test_only_the_named_command_is_built() -> None:
    group = program._command("run")
    assert list(group.commands) == ["run"]
    assert "run" in program._command(None).commands
    assert len(program._command(None).commands) > 1
