"""Fetching an object set's meshes: ``gbh objects fetch`` (and
``python -m gbh_drake.objects.fetch_sets MANIFEST.yaml [--cache-dir DIR]``).

Reads each manifest with :func:`gbh_drake.objects.sets.load_object_set` and hands its
``pypi://`` meshes to :func:`gbh_drake.objects.fetch.fetch_sources`.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from gbh_drake.objects.fetch import (
    SCHEME,
    Download,
    FetchError,
    Source,
    default_cache_dir,
    fetch_sources,
)


def read_manifest_entries(manifest) -> list[dict]:
    """The ``{"name", "mesh", "source"}`` of an object set's ``pypi://`` meshes (its manifest
    read and checked by :func:`gbh_drake.objects.sets.load_object_set`; built-in objects and
    local files need nothing fetched). ValueError naming the file, the entry and the field."""
    from gbh_drake.objects.sets import ObjectSetError, entry_name, load_object_set

    try:
        object_set = load_object_set(manifest)
    except ObjectSetError as exc:
        raise ValueError(str(exc)) from None
    return [{"name": entry_name(e), "mesh": e.mesh,
             "source": Source(e.source.package, e.source.version, e.source.archive,
                              e.source.license)}
            for e in object_set.entries if e.mesh.startswith(SCHEME)]


def main(argv: list[str] | None = None, *, download: Download | None = None) -> int:
    """``python -m gbh_drake.objects.fetch MANIFEST.yaml [--cache-dir DIR]``: fetch every mesh
    of an object set; prints one line per distribution and the cache folder. Exit 2 with a
    one-line message for a bad manifest, 1 when a fetch fails."""
    parser = argparse.ArgumentParser(prog="gbh objects fetch",
                                     description="Fetch an object set's meshes from PyPI.")
    parser.add_argument("manifest", nargs="+", help="object-set YAML file(s)")
    parser.add_argument("--cache-dir", default=None,
                        help="cache folder (default: $GBH_DRAKE_CACHE or ~/.cache/gbh_drake)")
    args = parser.parse_args(argv)
    try:
        entries = [e for m in args.manifest for e in read_manifest_entries(m)]
    except ValueError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    cache = Path(args.cache_dir) if args.cache_dir else default_cache_dir()
    try:
        results = fetch_sources(entries, cache, download=download, log=print)
    except (FetchError, ValueError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 1
    n_files = sum(len(r.files) for r in results)
    installed = sum(len(r.files) for r in results if r.installed)
    where = f": {n_files - installed} in {cache}, {installed} installed" if installed else \
        f" in {cache}"
    print(f"{n_files} mesh file(s) of {len(results)} distribution(s){where}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
