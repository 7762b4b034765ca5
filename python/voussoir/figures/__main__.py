"""python3 -m voussoir.figures FILE.h5 [-o DIR] [--format png,pdf,svg]: the charts of a
record, a sweep or a Monte Carlo study (voussoir.figures.USAGE)."""
import sys

from . import main

sys.exit(main())
