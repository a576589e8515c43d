"""A class list: which submitted file is which student, by the id the learning platform knows.

``students.csv`` has a header and one row per student::

    file,student_id,name
    alice.py,s1234567,Alice Martin
    submissions/bob.py,s7654321,Bob Stone

``file`` is the submission's file name (any folder in front is ignored: rows match
submissions by the file's stem, as the battery names algorithms); ``name`` is
optional. A submission without a row is reported under its file's stem; a row
without a submission is listed as "no submission" with mark 0.

>>> import tempfile, pathlib
>>> path = pathlib.Path(tempfile.mkdtemp()) / "students.csv"
>>> _ = path.write_text("file,student_id\\nalice.py,s1\\n")
>>> read_students(path)
[Student(stem='alice', student_id='s1', name='')]
"""

from __future__ import annotations

import csv
from dataclasses import dataclass
from pathlib import Path

from mimics.world.errors import MimicsError

STUDENTS_FILE = "students.csv"
MAX_ROWS = 100_000  # a class list, not a data set


@dataclass(frozen=True)
class Student:
    """One row of ``students.csv``.

    Attributes:
        stem: the submission's file name without folder and ``.py`` (``alice``).
        student_id: the id the teacher's learning platform knows.
        name: the student's name ("" when the file has no ``name`` column).
    """

    stem: str
    student_id: str
    name: str = ""


def read_students(path: str | Path) -> list[Student]:
    """The rows of a ``students.csv`` file.

    Raises:
        MimicsError: the file is missing or unreadable, lacks the ``file`` or
            ``student_id`` column, has an empty cell in them, or lists a file or an
            id twice; one line naming the file and the row.
    """
    source = Path(path)
    try:
        text = source.read_text(encoding="utf-8-sig")  # a spreadsheet's BOM is fine
    except FileNotFoundError:
        raise MimicsError(f"students file {source} does not exist") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise MimicsError(f"students file {source}: cannot read it ({exc})") from None
    reader = csv.DictReader(text.splitlines())
    columns = [c.strip() for c in reader.fieldnames or []]
    missing = [c for c in ("file", "student_id") if c not in columns]
    if missing:
        raise MimicsError(f"students file {source}: expected a header with the columns "
                          f"file,student_id[,name], got {','.join(columns) or 'nothing'}")
    students: list[Student] = []
    stems: set[str] = set()
    ids: set[str] = set()
    for number, raw in enumerate(reader, start=2):
        if number > MAX_ROWS:
            raise MimicsError(f"students file {source}: over {MAX_ROWS} rows")
        row = {(k or "").strip(): (v or "").strip() if isinstance(v, str) else ""
               for k, v in raw.items()}
        if not any(row.values()):
            continue  # a blank line
        file, student_id = row.get("file", ""), row.get("student_id", "")
        if not file or not student_id:
            raise MimicsError(f"students file {source}, line {number}: expected a file and a "
                              f"student_id, got {file!r} and {student_id!r}")
        stem = Path(file.replace("\\", "/")).name.removesuffix(".py")
        if stem in stems:
            raise MimicsError(f"students file {source}, line {number}: the file {file!r} is "
                              "listed twice")
        if student_id in ids:
            raise MimicsError(f"students file {source}, line {number}: the student_id "
                              f"{student_id!r} is listed twice")
        stems.add(stem)
        ids.add(student_id)
        students.append(Student(stem, student_id, row.get("name", "")))
    return students


def default_students_file(battery_source: str) -> Path | None:
    """``students.csv`` next to the battery file, when there is one."""
    if not battery_source:
        return None
    candidate = Path(battery_source).parent / STUDENTS_FILE
    return candidate if candidate.is_file() else None
