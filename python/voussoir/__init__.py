"""voussoir records from Python: open a run's HDF5 record into arrays with units, read its
summary and events as tables, draw the mechanism, the curves and the limit displacement domain
of a sweep, and run a case or a sweep through the voussoir program.

Debian packages: python3-h5py, python3-numpy, python3-matplotlib.
Install (Debian 12 refuses pip outside a virtual environment): python3 -m venv
--system-site-packages VENV, then VENV/bin/pip install --no-index --no-build-isolation --no-deps
./python (or use it in place: PYTHONPATH=python). docs/python.md says why.
"""
from .record import Record, Series, open_record
from .cli import run, sweep, read_table
from .draw import draw_mechanism, draw_curves, draw_domain

__version__ = "0.3.0"
__all__ = ["Record", "Series", "open_record", "run", "sweep", "read_table", "draw_mechanism",
           "draw_curves", "draw_domain"]
