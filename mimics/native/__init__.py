"""Algorithms written in C or C++: compiled on first use, cached, run like Python ones.

``build.py`` compiles a ``.c``/``.cpp`` file with the machine's compiler
(through cffi) and keeps the build in the user cache folder by content hash;
``adapter.py`` turns its entry points (``mimics_step`` or
``mimics_team_step``, declared in ``mimics/include/mimics.h``) into a
controller of the engine. See ``docs/how-to/c-algorithms.md``.
"""

from __future__ import annotations

#: Suffixes of algorithm files compiled as C or C++ (the catalog dispatches on them).
NATIVE_SUFFIXES = (".c", ".cpp", ".cc", ".cxx")
