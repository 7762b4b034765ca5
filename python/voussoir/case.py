"""A case in process: the library's vs_case, built from a case file, keyword arguments or a dict
of overrides, read back key by key. Every value goes through the library's own parser and range
check (vs_case_set), so a bad one raises CaseError with the library's message."""
import os

from . import _lib
from ._lib import ffi


def _key_name(name):
    """'support__alpha_deg' or 'support.alpha_deg' -> 'support.alpha_deg'."""
    return name if "." in name else name.replace("__", ".", 1)


def _value_text(v):
    if hasattr(v, "tolist"):  # a numpy number or array: as Python's
        v = v.tolist()
    if isinstance(v, bool):
        return "1" if v else "0"
    if isinstance(v, float):
        return repr(v)
    if isinstance(v, (list, tuple)):
        return ", ".join(_value_text(x) for x in v)
    if isinstance(v, os.PathLike):
        return os.fspath(v)
    return str(v)


def _overrides(overrides, kw):
    out = dict(overrides or {})
    out.update(kw)
    return [(_key_name(k), v) for k, v in out.items()]


class Case:
    """Every input parameter of a run, in the case file's units (mm, N/mm^3, deg).

    Case(**overrides) starts from the defaults (the reference specimen with k_n = 3 N/mm^3);
    Case.from_file(path, **overrides) from a case file. Overrides are keyword arguments
    section__key=value (arch__voussoirs=11) or a dict {"section.key": value}; a list is written
    comma-separated (arch.joint_positions). case["support.alpha_deg"] reads a value (a number,
    the name of a choice, or text), case.to_dict() all of them, case.set(...) changes values in
    place and case.copy(...) returns a changed copy."""

    def __init__(self, overrides=None, /, **kw):
        L = _lib.lib()
        self._c = ffi.new("vs_case *")
        L.vs_case_defaults(self._c)
        self.path = None
        self.set(overrides, **kw)

    @classmethod
    def from_file(cls, path, overrides=None, /, **kw):
        """The case file at path (INI, docs/case-file.md) with the overrides applied after it."""
        c = cls()
        err = _lib.new_error()
        path = os.fspath(path)
        _lib.raise_for(_lib.lib().vs_case_read(c._c, path.encode(), ffi.NULL, err), err)
        c.path = path
        return c.set(overrides, **kw)

    @classmethod
    def from_blocks(cls, blocks, overrides=None, /, *, ring=None, interfaces=None,
                    tolerance_mm=None, path=None, base=None, **kw):
        """A case whose arch is blocks built in Python (arch.shape = file): blocks is a blocks
        file's content as a dict ({"blocks": [...], "ring": [...], ...}, docs/blocks-file.md)
        or its list of blocks, each {"name", "polygon": [[x, z], ...] in mm (a list or an
        (n, 2) array), "support": "left"/"right" (absent: a block), "density_kg_m3"}, with ring
        (names from a left support to a right one), interfaces and tolerance_mm given apart.
        The file is written to path (kept), or to a temporary directory that lives as long as
        the case and its copies. base: the case the other keys come from (a Case or a case
        file's path; default the defaults); overrides as Case(); the blocks are read (and
        checked: CaseError naming the problem) when the case runs or validate() is called."""
        import json
        import tempfile
        doc = dict(blocks) if isinstance(blocks, dict) else {"blocks": list(blocks)}
        doc.setdefault("format", "voussoir-blocks 1")
        for k, v in (("ring", ring), ("interfaces", interfaces), ("tolerance_mm", tolerance_mm)):
            if v is not None:
                doc[k] = v
        doc["blocks"] = [dict(b, polygon=[[float(x), float(z)] for x, z in b["polygon"]])
                         if "polygon" in b else dict(b) for b in doc["blocks"]]
        keep = None
        if path is None:
            keep = tempfile.TemporaryDirectory(prefix="voussoir-blocks-")
            path = os.path.join(keep.name, "blocks.json")
        path = os.path.abspath(os.fspath(path))
        with open(path, "w") as f:
            json.dump(doc, f)
        c = (base.copy() if isinstance(base, Case) else
             cls.from_file(base) if base is not None else cls())
        c._blocks_dir = keep if keep is not None else getattr(c, "_blocks_dir", None)
        c.set({"arch.shape": "file", "arch.blocks_file": path})
        return c.set(overrides, **kw)

    @classmethod
    def from_text(cls, text, name="<text>", overrides=None, /, **kw):
        """A case from the text of a case file (name stands for the file in messages)."""
        c = cls()
        err = _lib.new_error()
        b = text.encode()
        _lib.raise_for(_lib.lib().vs_case_parse(c._c, name.encode(), b, len(b), err), err)
        return c.set(overrides, **kw)

    def set(self, overrides=None, /, **kw):
        """Apply overrides in place (each as the CLI's --set section.key=value); returns self.
        The case is unchanged by the one that fails (CaseError names it)."""
        L = _lib.lib()
        for key, v in _overrides(overrides, kw):
            err = _lib.new_error()
            _lib.raise_for(L.vs_case_set(self._c, f"{key}={_value_text(v)}".encode(), err), err)
        return self

    def copy(self, overrides=None, /, **kw):
        """A copy, with overrides applied to it."""
        c = Case.__new__(Case)
        c._c = ffi.new("vs_case *")
        ffi.memmove(c._c, self._c, ffi.sizeof("vs_case"))
        c.path = self.path
        c._blocks_dir = getattr(self, "_blocks_dir", None)  # from_blocks' file lives on
        return c.set(overrides, **kw)

    def validate(self):
        """Check the values against one another (vs_case_validate); raises CaseError."""
        err = _lib.new_error()
        _lib.raise_for(_lib.lib().vs_case_validate(self._c, err), err)
        return self

    @staticmethod
    def keys():
        """[(section.key, unit, kind)] of every key, kind 'int', 'float', 'name' or 'text'."""
        return [(k, u, kind) for k, (_, u, kind) in _key_table().items()]

    def __getitem__(self, name):
        name = _key_name(name)
        table = _key_table()
        if name not in table:
            raise KeyError(f"{name}: not a case key (Case.keys() lists them)")
        i, _, kind = table[name]
        L = _lib.lib()
        if kind == "path":
            buf = ffi.new("char[]", 4096)
            L.vs_case_text_key(self._c, i, ffi.NULL, ffi.NULL, buf, 4096)
            return ffi.string(buf).decode()
        if kind == "text":
            buf = ffi.new("char[]", 4096)
            L.vs_case_key_text(self._c, i, buf, 4096)
            return ffi.string(buf).decode()
        value = ffi.new("double *")
        L.vs_case_key(self._c, i, ffi.NULL, ffi.NULL, ffi.NULL, ffi.NULL, value)
        if kind == "name":
            return _lib.text(L.vs_case_key_name_of(i, int(value[0])))
        return int(value[0]) if kind == "int" else value[0]

    def to_dict(self):
        """{"arch.radius_mm": 300.0, ...}: every key's value."""
        return {k: self[k] for k in _key_table()}

    @property
    def span_mm(self):
        """The intrados span L that the study normalises by (NaN for a blocks file's arch
        without arch.span_mm)."""
        return _lib.lib().vs_case_span_mm(self._c)

    def __repr__(self):
        src = f"from {self.path!r}, " if self.path else ""
        return (f"<voussoir.Case {src}{self['arch.shape']}, {self['arch.voussoirs']} voussoirs, "
                f"alpha {self['support.alpha_deg']:g} deg, kn {self['joints.kn_N_mm3']:g} N/mm^3>")


_TABLE = None


def _key_table():
    """{section.key: (index, unit, kind)}, kind int, float, name (a choice), text (a list or a
    file name: vs_case_key_text) or path (a support's path: vs_case_text_key)."""
    global _TABLE
    if _TABLE is None:
        L = _lib.lib()
        c = ffi.new("vs_case *")
        L.vs_case_defaults(c)
        sec, key, unit = ffi.new("char **"), ffi.new("char **"), ffi.new("char **")
        is_int, value = ffi.new("int *"), ffi.new("double *")
        buf = ffi.new("char[]", 16)
        table = {}
        for i in range(L.vs_case_key_count()):
            L.vs_case_key(c, i, sec, key, unit, is_int, value)
            kind = "int" if is_int[0] else "float"
            if L.vs_case_key_text(c, i, buf, 16) == 1:
                kind = "text"
            elif L.vs_case_key_name_of(i, int(value[0])) != ffi.NULL:
                kind = "name"
            table[f"{_lib.text(sec[0])}.{_lib.text(key[0])}"] = (i, _lib.text(unit[0]), kind)
        for i in range(L.vs_case_text_key_count()):
            L.vs_case_text_key(c, i, sec, key, ffi.NULL, 0)
            table[f"{_lib.text(sec[0])}.{_lib.text(key[0])}"] = (i, "", "path")
        _TABLE = table
    return _TABLE
