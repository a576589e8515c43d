"""MkDocs hook: the command-line reference, generated from the Typer app at build time.

``docs/reference/cli.md`` holds the marker ``<!-- mimics-cli -->``; this hook
replaces it with one section per command, walking the Click command tree
(``typer.main.get_command``), so a new command appears without editing the page.
Run it alone to print the generated Markdown: ``python docs/gen_cli.py``.
"""

from __future__ import annotations

from typing import Any

import typer

MARKER = "<!-- mimics-cli -->"


def cli_markdown() -> str:
    """Markdown for every command of ``mimics``, depth first, in the app's order."""
    from mimics.interfaces.cli.program import app  # mounts every group of commands

    root = typer.main.get_command(app)
    return "\n".join(_sections(root, root.context_class(root, info_name="mimics"), 2))


def _sections(command: Any, ctx: Any, level: int) -> list[str]:
    name = ctx.command_path
    lines = [f"{'#' * level} `{name}`", ""]
    help_text = (command.help or "").strip()
    if help_text:
        lines += [_plain(help_text), ""]
    lines += ["```", command.get_usage(ctx).strip(), "```", ""]
    rows = [_param_row(param, ctx) for param in command.get_params(ctx)]
    rows = [row for row in rows if row]
    if rows:
        lines += ["| argument or option | what |", "|---|---|", *rows, ""]
    if hasattr(command, "list_commands"):  # a group (Typer may vendor its own Click)
        for sub_name in command.list_commands(ctx):
            sub = command.get_command(ctx, sub_name)
            if sub is None or sub.hidden:
                continue
            sub_ctx = sub.context_class(sub, info_name=sub_name, parent=ctx)
            lines += _sections(sub, sub_ctx, min(level + 1, 4))
    return lines


def _param_row(param: Any, ctx: Any) -> str:
    record = param.get_help_record(ctx)
    if record is None:  # an argument: Typer keeps its help in .help
        if getattr(param, "hidden", False):
            return ""
        label, text = param.human_readable_name.upper(), getattr(param, "help", "") or ""
    else:
        label, text = record
    return f"| `{_cell(label)}` | {_cell(text)} |"


def _cell(text: str) -> str:
    return " ".join(text.split()).replace("|", "\\|")


def _plain(text: str) -> str:
    """Click's help with its ``\\b`` no-rewrap markers dropped."""
    return "\n".join(line for line in text.splitlines() if line.strip() != "\b")


def on_page_markdown(markdown: str, page: Any, **_: Any) -> str:
    """Fill the CLI page's marker with the generated reference."""
    if MARKER in markdown:
        return markdown.replace(MARKER, cli_markdown())
    return markdown


if __name__ == "__main__":
    print(cli_markdown())
