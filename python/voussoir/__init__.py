"""voussoir records from Python: open a run's HDF5 record into arrays with units, read its
summary and events as tables, draw the mechanism, the curves and the limit displacement domain
of a sweep; build a Case (from a case file, keyword arguments, or blocks built in Python:
Case.from_blocks) and run it in this process (libvoussoir through cffi), alone, as a sweep, a
calibration or a Monte Carlo study, into arrays and pandas tables; or run the voussoir program
(voussoir.cli.run, voussoir.cli.sweep). The charts of `voussoir plot` are voussoir.figures'
(python3 -m voussoir.figures FILE.h5).

Debian packages: python3-h5py, python3-numpy, python3-matplotlib, python3-cffi; for tables
python3-pandas and python3-xarray (optional: imported when used).
Install (Debian 12 refuses pip outside a virtual environment): python3 -m venv
--system-site-packages VENV, then VENV/bin/pip install --no-index --no-build-isolation --no-deps
./python (or use it in place: PYTHONPATH=python). docs/python.md says why.
"""
from .record import Record, Series, open_record
from .cli import read_table
from . import cli
from ._lib import Error, CaseError, SolverError, library_path
from .case import Case
from .inprocess import run, Result, History, Hinge, Collapse, LimitPoint, Event
from .record import LoadCurve, FirstCrack
from .study import sweep, montecarlo, calibrate
from . import tables
from .tables import record_to_xarray
from .draw import draw_mechanism, draw_curves, draw_domain
from . import figures

__version__ = "0.5.0"
__all__ = ["Record", "Series", "open_record", "read_table", "draw_mechanism", "draw_curves",
           "draw_domain", "figures", "cli", "Case", "run", "Result", "History", "Hinge", "Collapse",
           "LimitPoint", "Event", "LoadCurve", "FirstCrack", "sweep", "montecarlo", "calibrate",
           "record_to_xarray", "tables", "Error", "CaseError", "SolverError", "library_path"]
