"""The mesh fetcher on archives built here: a wheel-like zip and an sdist-like tar.gz (real
extraction), and real pip on a local wheel with --no-index (no network)."""

import hashlib
import io
import tarfile
import zipfile

import pytest
import yaml
from mesh_shapes import CUBE_OBJ

from gbh_drake.objects.fetch import (
    FETCH_HINT,
    FetchError,
    PipDownloader,
    Source,
    default_cache_dir,
    fetch_sources,
    parse_mesh_uri,
    resolve,
    source_dir,
)
from gbh_drake.objects.fetch_sets import main, read_manifest_entries

MIT = b"MIT License\n"


def make_wheel(folder, name="toypkg", version="1.0"):
    """A minimal valid wheel: two meshes, a licence beside them, dist-info with its licence."""
    path = folder / f"{name}-{version}-py3-none-any.whl"
    info = f"{name}-{version}.dist-info"
    with zipfile.ZipFile(path, "w") as zf:
        zf.writestr(f"{name}/__init__.py", "")
        zf.writestr(f"{name}/assets/objects/LICENSE", b"asset licence\n")
        zf.writestr(f"{name}/assets/objects/mug/mug.obj", CUBE_OBJ)
        zf.writestr(f"{name}/assets/objects/mug/mug.mtl", b"newmtl m\n")
        zf.writestr(f"{name}/assets/objects/ring.obj", CUBE_OBJ)
        zf.writestr(f"{name}/assets/other/LICENSE", b"not ours\n")
        zf.writestr(f"{info}/METADATA",
                    f"Metadata-Version: 2.1\nName: {name}\nVersion: {version}\n")
        zf.writestr(f"{info}/WHEEL", "Wheel-Version: 1.0\nGenerator: test\nRoot-Is-Purelib: true\n"
                                     "Tag: py3-none-any\n")
        zf.writestr(f"{info}/licenses/LICENSE", MIT)
        zf.writestr(f"{info}/RECORD", "")
    return path


def make_sdist(folder, name="toysrc", version="2.0"):
    path = folder / f"{name}-{version}.tar.gz"
    top = f"{name}-{version}"
    with tarfile.open(path, "w:gz") as tf:
        for member, data in ((f"{top}/LICENSE.txt", MIT), (f"{top}/PKG-INFO", b"Name: x\n"),
                             (f"{top}/data/cup.obj", CUBE_OBJ), (f"{top}/data/big.bin", b"x" * 99)):
            info = tarfile.TarInfo(member)
            info.size = len(data)
            tf.addfile(info, io.BytesIO(data))
    return path


class LocalArchive:
    """A download that hands over a file made here and counts its calls."""

    def __init__(self, archive):
        self.archive, self.calls = archive, 0

    def __call__(self, source, dest):
        self.calls += 1
        dest.mkdir(parents=True, exist_ok=True)
        target = dest / self.archive.name
        target.write_bytes(self.archive.read_bytes())
        return target


def wheel_entries(*paths, version="1.0"):
    src = {"package": "toypkg", "version": version, "archive": "wheel", "license": "MIT"}
    return [{"mesh": f"pypi://toypkg/{p}", "source": src} for p in paths]


def test_wheel_extracts_only_the_needed_files_and_licences(tmp_path):
    archive = make_wheel(tmp_path)
    download = LocalArchive(archive)
    cache = tmp_path / "cache"
    entries = wheel_entries("toypkg/assets/objects/mug/mug.obj", "toypkg/assets/objects/ring.obj",
                            "toypkg/assets/objects/ring.obj")
    [result] = fetch_sources(entries, cache, download=download)
    assert download.calls == 1 and result.downloaded
    root = cache / "toypkg-1.0"
    got = sorted(str(p.relative_to(root)) for p in root.rglob("*") if p.is_file())
    assert got == ["SOURCE.yaml", "toypkg-1.0.dist-info/licenses/LICENSE",
                   "toypkg/assets/objects/LICENSE", "toypkg/assets/objects/mug/mug.obj",
                   "toypkg/assets/objects/ring.obj"]
    assert (root / "toypkg/assets/objects/mug/mug.obj").read_bytes() == CUBE_OBJ
    record = yaml.safe_load((root / "SOURCE.yaml").read_text())
    assert record["sha256"] == hashlib.sha256(archive.read_bytes()).hexdigest()
    assert (record["package"], record["version"], record["archive"], record["license"]) == (
        "toypkg", "1.0", "wheel", "MIT")
    assert record["file"] == archive.name and record["bytes"] == archive.stat().st_size
    assert resolve(entries[0]["mesh"], entries[0]["source"], cache) == \
        root / "toypkg/assets/objects/mug/mug.obj"


def test_cached_files_are_not_fetched_again_and_a_new_one_is(tmp_path):
    download = LocalArchive(make_wheel(tmp_path))
    cache = tmp_path / "cache"
    fetch_sources(wheel_entries("toypkg/assets/objects/ring.obj"), cache, download=download)
    [again] = fetch_sources(wheel_entries("toypkg/assets/objects/ring.obj"), cache,
                            download=download)
    assert download.calls == 1 and not again.downloaded
    fetch_sources(wheel_entries("toypkg/assets/objects/mug/mug.obj"), cache, download=download)
    assert download.calls == 2
    record = yaml.safe_load((cache / "toypkg-1.0" / "SOURCE.yaml").read_text())
    assert {"toypkg/assets/objects/ring.obj", "toypkg/assets/objects/mug/mug.obj"} <= set(
        record["files"])


def test_sdist_paths_include_its_top_folder(tmp_path):
    download = LocalArchive(make_sdist(tmp_path))
    src = Source("toysrc", "2.0", "sdist", "MIT")
    [result] = fetch_sources([("pypi://toysrc/toysrc-2.0/data/cup.obj", src)],
                             tmp_path / "c", download=download)
    root = tmp_path / "c" / "toysrc-2.0"
    assert (root / "toysrc-2.0/data/cup.obj").read_bytes() == CUBE_OBJ
    assert (root / "toysrc-2.0/LICENSE.txt").read_bytes() == MIT
    assert not (root / "toysrc-2.0/data/big.bin").exists()
    assert result.files == (root / "toysrc-2.0/data/cup.obj",)


def test_a_missing_path_names_the_package_and_the_path(tmp_path):
    download = LocalArchive(make_wheel(tmp_path))
    with pytest.raises(FetchError, match=r"toypkg==1.0 \(wheel\) has no 'toypkg/nope.obj'"):
        fetch_sources(wheel_entries("toypkg/nope.obj"), tmp_path / "c", download=download)
    assert not (tmp_path / "c" / "toypkg-1.0" / "SOURCE.yaml").exists()


def test_resolve_says_how_to_fetch(tmp_path):
    with pytest.raises(FileNotFoundError, match="gbh objects fetch"):
        resolve("pypi://toypkg/toypkg/a.obj", {"package": "toypkg", "version": "1.0"}, tmp_path)
    assert "./dev.sh setup" in FETCH_HINT


@pytest.mark.parametrize("uri", ["toypkg/a.obj", "pypi://toypkg", "pypi://toypkg/../x.obj",
                                 "pypi:///abs.obj", "pypi://toypkg//a.obj"])
def test_bad_uris_are_refused(uri):
    with pytest.raises(ValueError):
        parse_mesh_uri(uri)


def test_uri_must_name_the_source_distribution(tmp_path):
    with pytest.raises(ValueError, match="source.package"):
        resolve("pypi://other/a.obj", Source("toypkg", "1.0"), tmp_path)
    with pytest.raises(ValueError, match="archive"):
        Source("toypkg", "1.0", "egg")
    assert parse_mesh_uri("pypi://Toy_Pkg/a/b.obj") == ("Toy_Pkg", "a/b.obj")
    assert source_dir(Source("Toy_Pkg", "1.0"), tmp_path) == tmp_path / "toy-pkg-1.0"


def test_default_cache_dir_follows_the_environment(monkeypatch, tmp_path):
    monkeypatch.setenv("GBH_DRAKE_CACHE", str(tmp_path / "here"))
    assert default_cache_dir() == tmp_path / "here"
    monkeypatch.delenv("GBH_DRAKE_CACHE")
    assert default_cache_dir().parts[-2:] == (".cache", "gbh_drake")


def test_real_pip_on_a_local_wheel_and_its_failure(tmp_path):
    links = tmp_path / "links"
    links.mkdir()
    archive = make_wheel(links)
    download = PipDownloader(["--no-index", "--find-links", str(links)])
    cache = tmp_path / "cache"
    [result] = fetch_sources(wheel_entries("toypkg/assets/objects/ring.obj"), cache,
                             download=download)
    assert result.downloaded and result.files[0].read_bytes() == CUBE_OBJ
    record = yaml.safe_load((cache / "toypkg-1.0" / "SOURCE.yaml").read_text())
    assert record["sha256"] == hashlib.sha256(archive.read_bytes()).hexdigest()
    with pytest.raises(FetchError, match=r"toypkg==9.9 \(wheel\): pip download failed"):
        fetch_sources(wheel_entries("toypkg/assets/objects/ring.obj", version="9.9"), cache,
                      download=download)


def write_manifest(path, objects):
    path.write_text(yaml.safe_dump({"name": "t", "description": "d", "objects": objects}))
    return path


def test_manifest_entry_point(tmp_path, capsys):
    download = LocalArchive(make_wheel(tmp_path))
    src = {"package": "toypkg", "version": "1.0", "archive": "wheel", "license": "MIT",
           "license_note": "ignored here"}
    manifest = write_manifest(tmp_path / "set.yaml", [
        {"name": "a", "mesh": "pypi://toypkg/toypkg/assets/objects/ring.obj", "source": src,
         "mass": 0.1},
        {"name": "b", "mesh": "pypi://toypkg/toypkg/assets/objects/mug/mug.obj", "source": src,
         "mass": 0.1},
        {"builtin": "teapot"}])  # nothing to fetch for a built-in object
    assert [e["name"] for e in read_manifest_entries(manifest)] == ["a", "b"]
    assert main([str(manifest), "--cache-dir", str(tmp_path / "c")], download=download) == 0
    assert download.calls == 1
    assert "2 mesh file(s) of 1 distribution(s)" in capsys.readouterr().out


@pytest.mark.parametrize(("objects", "message"), [
    ([], r"objects \(line \d+\): list at least one object"),
    ([{"name": "a", "mass": 0.1, "source": {"package": "p", "version": "1", "license": "MIT"}}],
     r"objects\[0\] \(a\)\.mesh \(line \d+\): give the mesh file"),
    ([{"name": "a", "mass": 0.1, "mesh": "pypi://p/x.obj", "source": {"package": "p"}}],
     r"objects\[0\] \(a\)\.source\.version"),
    ([{"name": "a", "mass": 0.1, "mesh": "pypi://p", "source": {"package": "p", "version": "1",
                                                                 "license": "MIT"}}],
     r"objects\[0\] \(a\)\.mesh.*pypi://DISTRIBUTION/PATH"),
])
def test_bad_manifests_exit_2_naming_file_and_field(tmp_path, capsys, objects, message):
    manifest = write_manifest(tmp_path / "bad.yaml", objects)
    assert main([str(manifest), "--cache-dir", str(tmp_path / "c")]) == 2
    err = capsys.readouterr().err
    assert "bad.yaml" in err and len(err.strip().splitlines()) == 1
    with pytest.raises(ValueError, match=message):
        read_manifest_entries(manifest)


def test_a_distribution_installed_at_the_version_is_not_downloaded(tmp_path, installed_toypkg,
                                                                   capsys):
    """The installed files are the wheel's: nothing is downloaded for them (pybullet's 98 MiB
    wheel was, for one mug), and a path the distribution does not hold says the nearest one
    instead of downloading it to find out."""
    download = LocalArchive(make_wheel(tmp_path))
    [result] = fetch_sources(wheel_entries("toypkg/assets/objects/mug/mug.obj"),
                             tmp_path / "cache", download=download)
    assert download.calls == 0 and result.installed and not result.downloaded
    assert result.files == (installed_toypkg / "toypkg/assets/objects/mug/mug.obj",)
    assert not (tmp_path / "cache").exists()
    with pytest.raises(FetchError, match=r"toypkg==1.0 \(installed in .*site\) has no "
                                         r"'toypkg/assets/objects/mug/mugg.obj' \(did you mean "
                                         r"mug.obj\?\)"):
        fetch_sources(wheel_entries("toypkg/assets/objects/mug/mugg.obj"), tmp_path / "cache",
                      download=download)
    [other] = fetch_sources(wheel_entries("toypkg/assets/objects/ring.obj", version="2.0"),
                            tmp_path / "cache", download=LocalArchive(make_wheel(tmp_path,
                                                                                 version="2.0")))
    assert other.downloaded  # another version than the installed one: from PyPI
    src = {"package": "toypkg", "version": "1.0", "license": "MIT"}
    manifest = write_manifest(tmp_path / "set.yaml", [
        {"name": "a", "mesh": "pypi://toypkg/toypkg/assets/objects/ring.obj", "source": src,
         "mass": 0.1}])
    assert main([str(manifest), "--cache-dir", str(tmp_path / "c")], download=download) == 0
    assert download.calls == 0
    assert "toypkg==1.0 (wheel): 1 file(s) in " in capsys.readouterr().out


def test_an_archive_without_a_path_names_the_nearest(tmp_path):
    download = LocalArchive(make_wheel(tmp_path))
    with pytest.raises(FetchError, match=r"has no 'toypkg/assets/objects/rign.obj' \(did you "
                                         r"mean 'toypkg/assets/objects/ring.obj'\?\)"):
        fetch_sources(wheel_entries("toypkg/assets/objects/rign.obj"), tmp_path / "c",
                      download=download)
