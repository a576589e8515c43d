"""`mimics map import/show` and `mimics data get` through Typer's test runner."""

from pathlib import Path

import pytest
from typer.testing import CliRunner

from mimics.interfaces.cli.maps import app, data_app
from mimics.world.map_files import load_map
from mimics.world.stage_data import STAGE_FILES
from tests.local_servers import serve, stage_repository
from tests.stage import stage_file

runner = CliRunner()

SVG = ('<svg xmlns="http://www.w3.org/2000/svg" width="20" height="10" viewBox="0 0 20 10">'
       '<rect x="1" y="1" width="18" height="8"/><line x1="10" y1="1" x2="10" y2="6"/></svg>')


def one_line_error(result: object) -> str:
    """The error a failed command printed: exit status 2 and exactly one line."""
    assert result.exit_code == 2, result.output
    lines = result.output.strip().splitlines()
    assert len(lines) == 1, result.output
    assert lines[0].startswith("mimics: error: ")
    return lines[0]


def test_import_svg_and_show(tmp_path: Path) -> None:
    (tmp_path / "plan.svg").write_text(SVG)
    out = tmp_path / "plan.txt"
    result = runner.invoke(app, ["import", str(tmp_path / "plan.svg"), "--out", str(out),
                                 "--scale", "0.5"])
    assert result.exit_code == 0, result.output
    assert "5 segments" in result.output
    assert load_map(out).bounds == (0.0, 0.0, 10.0, 5.0)
    picture = tmp_path / "plan.png"
    result = runner.invoke(app, ["show", str(out), "--out", str(picture)])
    assert result.exit_code == 0, result.output
    assert picture.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_import_stage_bitmap_with_size_and_center(tmp_path: Path) -> None:
    bitmap = stage_file("cave_filled.png")
    out = tmp_path / "cave.toml"
    result = runner.invoke(app, ["import", str(bitmap), "--out", str(out), "--size", "16", "16",
                                 "--center", "1", "0"])
    assert result.exit_code == 0, result.output
    assert load_map(out).bounds == (-7.0, -8.0, 9.0, 8.0)
    shown = runner.invoke(app, ["show", "stage:cave", "--out", str(tmp_path / "cave.png")])
    assert shown.exit_code == 0, shown.output


@pytest.mark.parametrize(("args", "expected"), [
    (["import", "{tmp}/missing.svg", "--out", "{tmp}/m.txt"], "SVG file not found"),
    (["import", "{tmp}/bad.svg", "--out", "{tmp}/m.txt"], "bad.svg: not a valid SVG"),
    (["import", "{tmp}/plan.svg", "--out", "{tmp}/m.dxf"], "can save a map as"),
    (["import", "{tmp}/plan.svg", "--out", "{tmp}/m.txt", "--resolution", "0.1"],
     "option 'resolution' does not apply"),
    (["import", "{tmp}/plan.svg", "--out", "{tmp}/m.txt", "--center", "1", "2"],
     "give --size W H too"),
    (["show", "{tmp}/nothing.txt", "--out", "{tmp}/x.png"], "map file not found"),
    (["show", "stage:moon", "--out", "{tmp}/x.png"], "unknown built-in map"),
])
def test_bad_input_is_one_line_and_status_2(tmp_path: Path, args: list[str],
                                            expected: str) -> None:
    (tmp_path / "plan.svg").write_text(SVG)
    (tmp_path / "bad.svg").write_text("<svg")
    result = runner.invoke(app, [a.format(tmp=tmp_path) for a in args])
    assert expected in one_line_error(result)


def test_help_texts_come_from_docstrings() -> None:
    result = runner.invoke(app, ["--help"])
    assert "Turn a drawing or an occupancy image into a map" in result.output
    assert "Download a data set" in runner.invoke(data_app, ["--help"]).output


def test_data_get_stage_from_a_local_server(tmp_path: Path) -> None:
    repo = stage_repository(tmp_path / "repo")
    dest = tmp_path / "data" / "stage"
    with serve(repo) as url:
        result = runner.invoke(data_app, ["get", "stage", "--url", url, "--dest", str(dest)])
    assert result.exit_code == 0, result.output
    assert "checksums verified" in result.output
    assert sorted(p.name for p in dest.iterdir()) == sorted(STAGE_FILES)
    (repo / STAGE_FILES["hospital.png"].remote).write_bytes(b"corrupted")
    (dest / "hospital.png").unlink()
    with serve(repo) as url:
        failed = runner.invoke(data_app, ["get", "stage", "--url", url, "--dest", str(dest)])
    assert "checksum mismatch" in one_line_error(failed)


def test_data_get_unknown_set() -> None:
    assert "unknown data set 'moon'" in one_line_error(runner.invoke(data_app, ["get", "moon"]))
