# SPDX-License-Identifier: MPL-2.0
"""python3 -m libdf1.opcua: the same as the df1opcua command."""
import sys

from .cli import main

sys.exit(main())
