"""Inputs and outputs named by fsspec URLs (``s3://``, ``gs://``, ``file://``, ...).

The spatch binary reads and writes local paths only. A task whose input, plan or output
folder is a URL stages it: the input and the plan are downloaded once per worker process
into a local temporary folder (a worker that runs several tiles reuses them), the tile is
written locally, then uploaded. A plain path (no ``scheme://``) is used as it is, with no
fsspec import and no copy.
"""

from __future__ import annotations

import os
import shutil
import tempfile
import threading
from typing import Optional

_lock = threading.Lock()
_staged: dict[str, str] = {}
_folder: Optional[str] = None


def is_url(path: str) -> bool:
    """Whether ``path`` names an fsspec URL rather than a local path."""
    scheme, sep, _ = path.partition("://")
    return bool(sep) and scheme.isidentifier()


def _fs(url: str):
    import fsspec

    return fsspec.core.url_to_fs(url)


def _staging_folder() -> str:
    global _folder
    if _folder is None:
        _folder = tempfile.mkdtemp(prefix="spatch-dask-")
    return _folder


def local_copy(path: str) -> str:
    """A local path holding ``path``'s bytes: ``path`` itself when it is local, else a
    copy downloaded once per process (kept under the file's name in a private folder)."""
    if not is_url(path):
        return path
    fs, remote = _fs(path)
    info = fs.info(remote)
    # A changed file (another size or modification stamp) is downloaded again.
    stamp = next((str(info[k]) for k in ("mtime", "ETag", "LastModified", "created") if k in info), "")
    key = f"{path}\0{info.get('size')}\0{stamp}"
    with _lock:
        if key in _staged:
            return _staged[key]
        folder = tempfile.mkdtemp(dir=_staging_folder())
        local = os.path.join(folder, os.path.basename(remote.rstrip("/")) or "input")
        fs.get_file(remote, local)
        _staged[key] = local
        return local


def join(folder: str, name: str) -> str:
    """``folder/name`` for a local folder or a URL."""
    if is_url(folder):
        return folder.rstrip("/") + "/" + name
    return os.path.join(folder, name)


def make_folder(folder: str) -> None:
    """Creates ``folder`` (local or URL) if it does not exist."""
    if is_url(folder):
        fs, remote = _fs(folder)
        fs.makedirs(remote, exist_ok=True)
    else:
        os.makedirs(folder, exist_ok=True)


def upload(local: str, target: str) -> None:
    """Copies the local file ``local`` to ``target`` (a URL), then removes ``local``."""
    fs, remote = _fs(target)
    fs.put_file(local, remote)
    os.remove(local)


def download_folder_files(folder: str, names, into: str) -> None:
    """Copies ``folder/NAME`` (a URL folder) to ``into/NAME`` for each name."""
    fs, remote = _fs(folder)
    for name in names:
        fs.get_file(remote.rstrip("/") + "/" + name, os.path.join(into, name))


def read_text(path: str) -> str:
    """The text of a local file or a URL."""
    if not is_url(path):
        with open(path, encoding="utf-8") as f:
            return f.read()
    fs, remote = _fs(path)
    with fs.open(remote, "rb") as f:
        return f.read().decode("utf-8")


def scratch_folder() -> str:
    """A fresh local folder for one task's outputs (remove it with ``shutil.rmtree``)."""
    return tempfile.mkdtemp(dir=_staging_folder())


def remove(folder: str) -> None:
    """Removes a folder made by :func:`scratch_folder`."""
    shutil.rmtree(folder, ignore_errors=True)
