"""Compiling a C or C++ algorithm file once, and finding the build again while it is unchanged.

The user's file is compiled on its own with the machine's compiler (so that
an error names the user's file and line), then linked with the host side
(``host.c``) into a Python extension by cffi in API mode. Builds live in the
user cache folder (``platformdirs.user_cache_dir("mimics")/native``, or
``$MIMICS_CACHE_DIR/native``), one folder per content hash of everything that
goes into them: the source, the header, the host code, compiler and flags, the
Python ABI and cffi's version. A build is made in a temporary folder and
renamed into place in one step, so battery workers starting together never
see half a build; whoever renames first wins and the others use that build.

Usage (compiles on the first call, a cache hit afterwards)::

    build = load_native("examples/c/go_to_goal.c")
    build.compiled, build.folder
"""

from __future__ import annotations

import contextlib
import hashlib
import importlib.machinery
import importlib.util
import os
import re
import shlex
import shutil
import subprocess
import sys
import sysconfig
import tempfile
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType
from typing import Any

from mimics.world.errors import AlgorithmError, MimicsError

#: Environment variable naming the cache folder (tests point it at a temporary one).
CACHE_ENV = "MIMICS_CACHE_DIR"
#: File suffixes compiled as C++ (the others of ``NATIVE_SUFFIXES`` as C).
CXX_SUFFIXES = (".cpp", ".cc", ".cxx")
#: Flags for the user's file: optimised, position-independent, and a*b+c never fused
#: into one rounding (so that arithmetic rounds as NumPy's does).
FLAGS = ("-O2", "-fPIC", "-ffp-contract=off")
#: The ABI of ``mimics.h`` this version of mimics speaks.
ABI_VERSION = 1

_HERE = Path(__file__).parent
HOST_SOURCE = _HERE / "host.c"

# What Python sees of the header and the host (cffi fills in the layouts: "...").
CDEF = """
#define MIMICS_ABI_VERSION ...
#define MIMICS_MEMORY_BYTES ...
#define MIMICS_TEAM_MEMORY_BYTES ...
typedef struct mimics_message { int sender; int size; const unsigned char *data; ...; }
    mimics_message;
typedef struct mimics_robot { int id; int inbox_count; const mimics_message *inbox;
    void *memory; int stalled; ...; } mimics_robot;
typedef struct mimics_outgoing { int to; int size; unsigned char data[...]; ...; }
    mimics_outgoing;
typedef struct mimics_output { double speed; double heading; int log_size; char log[...];
    int outbox_count; mimics_outgoing outbox[...]; ...; } mimics_output;
typedef struct mimics_team {
    int count; int beams; double time; double dt; const int64_t *ids;
    const double *pose; const double *true_pose; const double *velocity;
    const double *odometry; const double *goal; const double *ranges; const double *angles;
    const int64_t *beam_count; const double *max_range; const double *max_speed;
    const double *length; const double *width; int comms_count; const double *comms;
    void *memory; const int64_t *stalled; ...; } mimics_team;
typedef struct mimics_host_world {
    int beams; double time; double dt; double comm_range;
    const double *measured_pose; const double *pose; const double *measured_velocity;
    const double *velocity; const double *measured_acceleration; const double *odometry;
    const double *goal; const double *scan; const double *beam_offsets;
    const int64_t *beam_count; const double *max_range; const double *half_length;
    const double *half_width; const double *kv; const unsigned char *stalled;
    int comms_count; const double *comms;
    double *comms_scratch; double *reference; double *user_time; int64_t *current;
    ...; } mimics_host_world;
int mimics_host_entry_points(void);
int mimics_host_abi(void);
int mimics_host_run(mimics_host_world *w, mimics_robot *robots, mimics_output *outputs,
                    const int64_t *ids, int k, int reset, int *flags, int *codes);
int mimics_host_team(const mimics_team *team, double *speed, double *heading, int reset);
int mimics_host_arm_cuts(int signum);
int mimics_host_was_cut(void);
"""

_ERROR_LINE = re.compile(r"^(?P<where>.+?:\d+(?::\d+)?): (?:fatal )?error: (?P<message>.+)$",
                         re.MULTILINE)


class CompileError(AlgorithmError):
    """The user's file did not compile: the compiler's first error, with file and line."""


@dataclass(frozen=True)
class NativeBuild:
    """A loaded build of one algorithm file.

    Attributes:
        source: the algorithm file.
        folder: its folder in the cache.
        module: the extension module (``module.ffi``, ``module.lib``).
        compiled: whether this call compiled it (False: found in the cache).
    """

    source: Path
    folder: Path
    module: ModuleType
    compiled: bool

    @property
    def ffi(self) -> Any:
        """The module's cffi ``FFI``."""
        return self.module.ffi

    @property
    def lib(self) -> Any:
        """The module's functions and constants."""
        return self.module.lib


def include_dir() -> Path:
    """The folder holding ``mimics.h`` (for users' own build systems)."""
    return _HERE.parent / "include"


def cache_root() -> Path:
    """Where builds are kept: ``$MIMICS_CACHE_DIR/native`` or the user cache folder."""
    chosen = os.environ.get(CACHE_ENV)
    if chosen:
        return Path(chosen).expanduser() / "native"
    import platformdirs

    return Path(platformdirs.user_cache_dir("mimics", appauthor=False)) / "native"


def compiler_for(path: Path) -> list[str]:
    """The compiler command for ``path``: ``$CC``/``$CXX``, else Python's own, else gcc/g++."""
    cxx = path.suffix.lower() in CXX_SUFFIXES
    variable = "CXX" if cxx else "CC"
    command = os.environ.get(variable) or sysconfig.get_config_var(variable) or (
        "g++" if cxx else "gcc")
    words = shlex.split(command)
    if shutil.which(words[0]) is None:
        raise MimicsError(f"{path}: no {'C++' if cxx else 'C'} compiler found ({words[0]!r}); "
                          "install one (Debian: apt install gcc g++ libc6-dev) or set "
                          f"${variable}")
    return words


_loaded: dict[str, NativeBuild] = {}  # builds already imported by this process, by hash


def load_native(path: str | Path) -> NativeBuild:
    """The build of a C/C++ algorithm file: from this process, the cache, or compiled now.

    Raises:
        CompileError: the file does not compile (the compiler's first error).
        MimicsError: no such file, no compiler, or a build of another ABI.
    """
    source = Path(path)
    if not source.is_file():
        raise AlgorithmError(f"algorithm file {source} does not exist")
    compiler = compiler_for(source)
    key = _content_key(source, compiler)
    if key in _loaded:
        return _loaded[key]
    root = cache_root()
    folder = root / key
    library = _library_in(folder)
    compiled = False
    if library is None:
        root.mkdir(parents=True, exist_ok=True)
        _build(source, compiler, key, root)
        compiled = True
        library = _library_in(folder)
        if library is None:
            raise MimicsError(f"{source}: the build in {folder} is incomplete")
    build = NativeBuild(source, folder, _import(source, library, key), compiled)
    version = build.lib.mimics_host_abi()
    if version != ABI_VERSION:
        found = ("it does not include mimics.h" if version < 0
                 else f"it was compiled against mimics.h ABI version {version}")
        raise AlgorithmError(f"{source}: {found}; this mimics speaks ABI version "
                             f"{ABI_VERSION} (#include \"mimics.h\" from `mimics include-dir`)")
    _loaded[key] = build
    return build


def _module_name(key: str) -> str:
    return f"_mimics_native_{key[:20]}"


def _content_key(source: Path, compiler: list[str]) -> str:
    """A hash of everything that makes the build what it is."""
    digest = hashlib.sha256()
    parts = [b"mimics-native", str(ABI_VERSION).encode(), source.read_bytes(),
             (include_dir() / "mimics.h").read_bytes(), HOST_SOURCE.read_bytes(), CDEF.encode(),
             " ".join([*compiler, *FLAGS]).encode(), source.suffix.lower().encode(),
             sys.implementation.cache_tag.encode(),
             str(sysconfig.get_config_var("EXT_SUFFIX")).encode(), _cffi_version().encode()]
    for part in parts:
        digest.update(len(part).to_bytes(8, "little"))
        digest.update(part)
    return digest.hexdigest()[:40]


def _cffi_version() -> str:
    try:
        import cffi
    except ImportError:
        raise MimicsError("C/C++ algorithms need the cffi package: pip install cffi") from None
    return cffi.__version__


def _library_in(folder: Path) -> Path | None:
    suffix = sysconfig.get_config_var("EXT_SUFFIX") or ".so"
    candidate = folder / f"{_module_name(folder.name)}{suffix}"
    return candidate if candidate.is_file() else None


def _build(source: Path, compiler: list[str], key: str, root: Path) -> None:
    """Compile ``source`` and the host into ``root/key``, atomically."""
    import cffi

    work = Path(tempfile.mkdtemp(prefix=".build-", dir=root))
    try:
        user_object = work / "algorithm.o"
        command = [*compiler, *FLAGS, "-I", str(include_dir()), "-c", str(source), "-o",
                   str(user_object)]
        # messages in English whatever the locale: the first error is found by its form
        done = subprocess.run(command, capture_output=True, text=True, check=False,
                              env={**os.environ, "LC_ALL": "C"})
        if done.returncode != 0:
            raise CompileError(_first_error(done.stdout + done.stderr, source, done.returncode))
        ffi = cffi.FFI()
        ffi.cdef(CDEF)
        cxx = source.suffix.lower() in CXX_SUFFIXES
        ffi.set_source(_module_name(key), HOST_SOURCE.read_text(),
                       include_dirs=[str(include_dir())], extra_objects=[str(user_object)],
                       libraries=["m", *(["stdc++"] if cxx else [])])
        with _quiet():
            built = Path(ffi.compile(tmpdir=str(work), verbose=False))
        result = work / "result"
        result.mkdir()
        built.rename(result / built.name)
        (result / "source.txt").write_text(f"{source.resolve()}\n")
        with contextlib.suppress(OSError):  # another process finished first: use its build
            result.rename(root / key)
    except CompileError:
        raise
    except Exception as exc:  # the host side failing to build is our fault, said in one line
        raise MimicsError(f"{source}: building the extension failed: {exc}") from exc
    finally:
        shutil.rmtree(work, ignore_errors=True)


def _first_error(output: str, source: Path, status: int) -> str:
    """The compiler's first error as one line ``file:line:col: message``."""
    found = _ERROR_LINE.search(output)
    if found:
        return f"{found['where']}: error: {found['message'].strip()}"
    lines = [line for line in output.splitlines() if line.strip()]
    detail = lines[0].strip() if lines else "no message"
    return f"{source}: the compiler failed (exit status {status}): {detail}"


@contextlib.contextmanager
def _quiet() -> Any:
    """Silence what setuptools and the compiler print while building the host side."""
    sys.stdout.flush()
    sys.stderr.flush()
    saved = [os.dup(1), os.dup(2)]
    with open(os.devnull, "w") as null:
        os.dup2(null.fileno(), 1)
        os.dup2(null.fileno(), 2)
    try:
        yield
    finally:
        os.dup2(saved[0], 1)
        os.dup2(saved[1], 2)
        for fd in saved:
            os.close(fd)


def _import(source: Path, library: Path, key: str) -> ModuleType:
    name = _module_name(key)
    if name in sys.modules:
        return sys.modules[name]
    loader = importlib.machinery.ExtensionFileLoader(name, str(library))
    spec = importlib.util.spec_from_file_location(name, library, loader=loader)
    if spec is None:
        raise MimicsError(f"{source}: cannot load its build {library}")
    module = importlib.util.module_from_spec(spec)
    try:
        loader.exec_module(module)
    except ImportError as exc:  # e.g. an undefined symbol: a function declared, never defined
        raise AlgorithmError(f"{source}: its build cannot be loaded: {exc}") from None
    sys.modules[name] = module
    return module
