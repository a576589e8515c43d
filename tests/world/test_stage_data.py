"""Downloading the Stage data from a local HTTP server laid out like the Stage repository."""

import socket
from pathlib import Path

import pytest

from mimics.world.errors import MimicsError
from mimics.world.stage_data import STAGE_FILES, download_stage
from tests.local_servers import QuietHandler, serve, stage_repository


def test_download_checks_and_writes_every_file(tmp_path: Path) -> None:
    repo = stage_repository(tmp_path / "repo")
    seen: list[tuple[str, int, int | None]] = []
    with serve(repo) as url:
        paths = download_stage(tmp_path / "data" / "stage", base_url=url,
                               progress=lambda *event: seen.append(event))
        assert sorted(p.name for p in paths) == sorted(STAGE_FILES)
        for name, spec in STAGE_FILES.items():
            assert (tmp_path / "data" / "stage" / name).read_bytes() == (
                repo / spec.remote).read_bytes()
        assert {name for name, _, _ in seen} == set(STAGE_FILES)
        last = {name: received for name, received, _ in seen}
        assert last == {name: (repo / spec.remote).stat().st_size
                        for name, spec in STAGE_FILES.items()}
        QuietHandler.requests.clear()
        download_stage(tmp_path / "data" / "stage", base_url=url)  # all present: no requests
        assert QuietHandler.requests == []
    assert not list((tmp_path / "data" / "stage").glob(".*part"))


def test_bad_checksum_is_refused_and_not_written(tmp_path: Path) -> None:
    repo = stage_repository(tmp_path / "repo")
    (repo / "worlds" / "benchmark" / "cave.world").write_text("# tampered\n")
    dest = tmp_path / "stage"
    with serve(repo) as url, pytest.raises(MimicsError) as info:
        download_stage(dest, base_url=url)
    message = str(info.value)
    assert "cave.world: checksum mismatch" in message and "\n" not in message
    assert not (dest / "cave.world").exists()
    assert not list(dest.glob(".*part"))


def test_missing_file_on_the_server(tmp_path: Path) -> None:
    repo = stage_repository(tmp_path / "repo")
    (repo / "COPYING.txt").unlink()
    with serve(repo) as url, pytest.raises(MimicsError, match=r"COPYING\.txt: HTTP 404"):
        download_stage(tmp_path / "stage", base_url=url)


def test_offline_is_one_line(tmp_path: Path) -> None:
    with socket.socket() as probe:  # a port nobody listens on
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    with pytest.raises(MimicsError, match=r"cannot download http://127\.0\.0\.1:\d+/.*offline"):
        download_stage(tmp_path / "stage", base_url=f"http://127.0.0.1:{port}", timeout=5)
