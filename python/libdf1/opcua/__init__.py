# SPDX-License-Identifier: MPL-2.0
"""df1opcua: a DF1 line served as an OPC UA server (the package's [opcua] extra, on asyncua).

    df1opcua -d /dev/ttyUSB0 --map tags.csv          # or: python3 -m libdf1.opcua ...

The poll engine (libdf1.Poller) reads the mapping's tags; every row becomes a
Variable Objects/LINE/stationN/TAG (NodeId ns=N;s=LINE.stationN.TAG) whose
value, StatusCode and SourceTimestamp follow the tag's quality; a write to a
ReadWrite row is executed once on the PLC and answered Good only when the PLC
has acknowledged it. See df1opcua(1).
"""
