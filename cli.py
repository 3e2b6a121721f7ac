#!/usr/bin/env python3
"""Thin entry point: `python cli.py generate FILE -o DIR` (same as the installed `mtlxgen`)."""
import sys

from mtlxgen.apps.cli import main

if __name__ == "__main__":
    sys.exit(main())
