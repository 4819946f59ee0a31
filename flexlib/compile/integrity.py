"""Integrity of what the disk cache reads back: files against their manifest, CasADi streams before parsing.

A compiled library is loaded (``dlopen``) and a serialized CasADi function is parsed only after these checks:
the file is a regular file of this user that no one else can write and matches the size and SHA-256 recorded
by the process that wrote it; the stream is a plain ``SXFunction`` of the expected name with no reference to
external code (deserializing an ``External`` function would load a shared library).
"""

from __future__ import annotations

import hashlib
import os
import stat
from pathlib import Path

import casadi as ca
import numpy as np

__all__ = ["check_serialized", "deserialize_function", "file_problem", "sha256_file"]


def file_problem(path: Path, sha256: str | None = None, size: int | None = None) -> str | None:
    """Why the file ``path`` must not be used, or None.

    It must be a regular file (not a link) owned by this user and not writable by others, and match its
    manifest entry (``size`` [bytes] and ``sha256``) when one is given.
    """
    try:
        st = path.lstat()
    except OSError as exc:
        return f"cannot read it: {exc.strerror or exc}"
    if not stat.S_ISREG(st.st_mode):
        return "not a regular file"
    if hasattr(os, "getuid") and st.st_uid != os.getuid():
        return f"owned by uid {st.st_uid}, not by this user"
    if st.st_mode & 0o022:
        return "writable by other users"
    if size is not None and st.st_size != size:
        return f"size {st.st_size} bytes, manifest says {size}"
    if sha256 is not None and sha256_file(path) != sha256:
        return "SHA-256 differs from the manifest"
    return None


def sha256_file(path: Path) -> str:
    """SHA-256 (hex) of the file ``path``, read in 1 MiB chunks."""
    h = hashlib.sha256()
    with path.open("rb") as fh:
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def _decode(text: str) -> bytes:
    """CasADi's serialized text (two letters a–p per byte, low nibble first) as bytes."""
    # uint8 arithmetic throughout (no int16 copies of a multi-megabyte stream): a letter below 'a' wraps
    # around to > 15 and is refused by the same test as one above 'p'
    codes = np.frombuffer(text.encode("ascii"), dtype=np.uint8) - np.uint8(97)
    if len(codes) % 2 or len(codes) == 0 or codes.max() > 15:
        raise ValueError("not a CasADi serialized stream")
    return (codes[0::2] | (codes[1::2] << np.uint8(4))).tobytes()


def check_serialized(text: str, name: str, full: bool = True) -> None:
    """Refuse a serialized stream that is not a plain ``SXFunction`` named ``name`` (checked before CasADi
    reads it: deserializing an ``External`` function would load a shared library). ``full=False`` checks the
    header only (the type and name); ``full=True`` also refuses any reference to external code in the body."""
    try:
        data = _decode(text if full else text[:160])
    except (UnicodeEncodeError, ValueError) as exc:
        raise ValueError(f"function {name!r}: {exc}") from None
    head = b"\x0a\x00\x00\x00SXFunction"
    if data[18:18 + len(head)] != head:
        raise ValueError(f"function {name!r}: the stream is not an SXFunction")
    label = len(name).to_bytes(4, "little") + name.encode()
    if data[36:36 + len(label)] != label:
        raise ValueError(f"function {name!r}: the stream holds another function")
    if full and (b"External" in data or b"Callback" in data):
        raise ValueError(f"function {name!r}: the stream refers to external code")


def deserialize_function(text: str, name: str) -> ca.Function:
    """Deserialize a checked SX function stream (:func:`check_serialized`)."""
    check_serialized(text, name)
    return ca.Function.deserialize(text)
