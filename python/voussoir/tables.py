"""Optional imports (pandas, xarray) with a message that says how to get them."""


def pandas():
    try:
        import pandas as pd
    except ImportError as e:
        raise ImportError("this needs pandas: apt-get install python3-pandas (Debian 12), or "
                          "pip install pandas in the venv") from e
    return pd


def xarray():
    try:
        import xarray as xr
    except ImportError as e:
        raise ImportError("this needs xarray: apt-get install python3-xarray (Debian 12), or "
                          "pip install xarray in the venv") from e
    return xr


def record_to_xarray(record):
    """A run's record (a path or an open voussoir.Record) as an xarray Dataset, read into memory.

    Dimensions: state (one per recorded state, coordinate time in s), block, joint, joint_point
    (the two ends of each joint, intrados first), and for an
    observable of vectors its component (block_position_component: ux, uz, theta). Each
    observable of /observables is a variable with its unit in attrs["units"]; one whose columns
    are different quantities (reactions, energy, supports, solver, support_displacement) is
    split into a variable per column, named by the column (right_Fz, kinetic, ...), or
    OBSERVABLE_COLUMN where that name is taken. attrs: status, case (the case file's text) and
    every case key ("arch.radius_mm", in the case's units)."""
    from .record import Record
    xr = xarray()
    rec = record if isinstance(record, Record) else Record(record)
    try:
        nb = rec.geometry("block_mass").values.shape[0]
        nj = rec.geometry("joint_length").values.shape[0]
        t = rec.time()
        data, split = {}, []
        for name in rec.series_names():
            s = rec.series(name)
            v = s.values
            units = s.unit.split(",")
            if v.ndim == 2 and s.columns:
                split.append((name, s, units))
                continue
            dims = ["state"]
            for k, n in enumerate(v.shape[1:]):
                last = k == v.ndim - 2
                dims.append(f"{name}_component" if last and s.columns else
                            "block" if n == nb else "joint" if n == nj else
                            "joint_point" if n == 2 * nj else f"{name}_{k + 1}")
            coords = {f"{name}_component": s.columns} if s.columns else {}
            attrs = {"units": units[0] if len(set(units)) == 1 else s.unit}
            data[name] = xr.DataArray(v, dims=dims, coords=coords, attrs=attrs)
        for name, s, units in split:
            for k, col in enumerate(s.columns):
                key = col if col not in data and col not in rec.series_names() else f"{name}_{col}"
                u = units[k] if len(units) > 1 else units[0]
                data[key] = xr.DataArray(s.values[:, k], dims=["state"], attrs={"units": u})
        ds = xr.Dataset(data, coords={"time": ("state", t.values, {"units": t.unit})})
        ds.attrs["status"] = rec.status
        ds.attrs["case"] = rec.case_text
        ds.attrs.update(rec.parameters())
        return ds
    finally:
        if rec is not record:
            rec.close()
