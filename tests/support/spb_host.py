#!/usr/bin/env python3
# SPDX-License-Identifier: MPL-2.0
# spb_host.py - an independent Sparkplug B host for the gateway's tests,
# built on pysparkplug (PyPI) and paho-mqtt, never on df1gw's code:
#   record PORT FILE     every message on spBv1.0/#, decoded, one JSON line each
#   ncmd PORT GROUP EDGE [alias]       Node Control/Rebirth = true
#   dcmd PORT GROUP EDGE DEVICE NAME TYPE VALUE [TS]   one metric written
#   dcmd-dup PORT GROUP EDGE DEVICE NAME TYPE VALUE TS|none   the same DCMD sent twice
#                        over a plain socket, the second a resend with MQTT's DUP flag
#                        (QoS 1, the same packet id); "none": no timestamp at all
#   state PORT HOST online|offline [TS]  the primary host's retained STATE (3.0 JSON)
#   check FILE           the Sparkplug rules over a recording (see check())
#   alias FILE NAME      the alias of metric NAME in the last DBIRTH recorded (dcmd takes #ALIAS)
#   has FILE FROM EXPR   exit 0 when the Python EXPR holds over R, the records from line FROM on
# Exit 77 when pysparkplug is missing (the test then says SKIP).
import json
import sys
import time

try:
    import paho.mqtt.client as mqtt
    import pysparkplug as spb
    from pysparkplug import _protobuf as pb
except ImportError:
    sys.exit(77)

DECODERS = {"NBIRTH": spb.NBirth, "DBIRTH": spb.DBirth, "NDATA": spb.NData, "DDATA": spb.DData,
            "NDEATH": spb.NDeath, "DDEATH": spb.DDeath, "NCMD": spb.NCmd, "DCMD": spb.DCmd}


def client(port):
    c = mqtt.Client(client_id="", clean_session=True)
    c.connect("127.0.0.1", int(port), 30)
    return c


def signed(v):
    """An Int8/16/32 property from its uint32 int_value (the specification's
    carrier for signed types): two's complement at the type's width."""
    bits = {1: 8, 2: 16, 3: 32}.get(v.type)
    x = v.int_value
    if bits and x >= 1 << (bits - 1):
        x -= 1 << bits
    return x


def props(raw):
    """Quality and Reason properties per metric name (or alias), from the raw protobuf."""
    p = pb.Payload.FromString(raw)
    out = {}
    for m in p.metrics:
        if m.HasField("properties"):
            d = {}
            for k, v in zip(m.properties.keys, m.properties.values):
                d[k] = v.string_value if v.HasField("string_value") else signed(v)
            out[m.name or str(m.alias)] = d
    return out


def record(port, path):
    out = open(path, "a", buffering=1)
    births = {}

    def on_message(c, u, msg):
        parts = msg.topic.split("/")
        rec = {"topic": msg.topic, "retain": bool(msg.retain), "qos": msg.qos, "t": time.time()}
        if parts[1] == "STATE":
            rec["type"] = "STATE"
            out.write(json.dumps(rec) + "\n")
            return
        kind = parts[2]
        rec["type"] = kind
        rec["device"] = parts[4] if len(parts) > 4 else None
        try:
            key = (parts[3], rec["device"])
            p = DECODERS[kind].decode(msg.payload, birth=births.get(key))
            if kind in ("NBIRTH", "DBIRTH"):
                births[key] = p
                if kind == "NBIRTH":
                    births[(parts[3], None)] = p
            if kind == "NDEATH":
                rec["bdseq"] = p.bd_seq_metric.value
                rec["metrics"] = [{"name": p.bd_seq_metric.name, "datatype": p.bd_seq_metric.datatype.name,
                                   "value": p.bd_seq_metric.value}]
            else:
                rec["seq"] = getattr(p, "seq", None)
                rec["timestamp"] = getattr(p, "timestamp", None)
                ms = []
                for m in getattr(p, "metrics", ()):
                    v = m.value
                    if isinstance(v, (bytes, tuple, list)):
                        v = list(v)
                    if isinstance(v, float):
                        v = round(v, 6)
                    ms.append({"name": m.name, "alias": m.alias, "datatype": m.datatype.name, "value": v,
                               "is_null": m.is_null, "timestamp": m.timestamp,
                               "is_historical": m.is_historical})
                rec["metrics"] = ms
                rec["props"] = props(msg.payload)
                rec["wire_names"] = [m.name for m in pb.Payload.FromString(msg.payload).metrics]
        except Exception as e:  # noqa: BLE001 - a message pysparkplug cannot decode is a finding
            rec["error"] = "%s: %s" % (type(e).__name__, e)
        out.write(json.dumps(rec) + "\n")

    c = client(port)
    c.on_message = on_message
    c.subscribe("spBv1.0/#", 1)
    c.loop_forever()


def publish(port, topic, payload, retain=False):
    c = client(port)
    c.loop_start()
    c.publish(topic, payload, qos=1, retain=retain).wait_for_publish(5)
    c.loop_stop()
    c.disconnect()


def ncmd(port, group, edge, alias=None):
    m = spb.Metric(timestamp=spb.get_current_timestamp(), name="Node Control/Rebirth",
                   datatype=spb.DataType.BOOLEAN, value=True)
    p = spb.NCmd(timestamp=spb.get_current_timestamp(), metrics=(m,))
    publish(port, "spBv1.0/%s/NCMD/%s" % (group, edge), p.encode(include_dtypes=True))


def dcmd_payload(name, dtype, value, ts):
    dt = spb.DataType[dtype]
    if dt in (spb.DataType.FLOAT, spb.DataType.DOUBLE):
        v = float(value)
    elif dt == spb.DataType.BOOLEAN:
        v = value in ("1", "true", "True")
    elif dt == spb.DataType.STRING:
        v = value
    else:
        v = int(value)
    now = int(ts) if ts else spb.get_current_timestamp()
    if name.startswith("#"):  # by alias only
        m = spb.Metric(timestamp=now, name=None, alias=int(name[1:]), datatype=dt, value=v)
    else:
        m = spb.Metric(timestamp=now, name=name, datatype=dt, value=v)
    return spb.DCmd(timestamp=now, metrics=(m,)).encode(include_dtypes=True)


def dcmd(port, group, edge, device, name, dtype, value, ts=None):
    publish(port, "spBv1.0/%s/DCMD/%s/%s" % (group, edge, device), dcmd_payload(name, dtype, value, ts))


def mqtt_string(s):
    b = s.encode()
    return len(b).to_bytes(2, "big") + b


def mqtt_packet(first, body):
    n, rl = len(body), b""
    while True:
        d, n = n % 128, n // 128
        rl += bytes([d | (0x80 if n else 0)])
        if not n:
            return bytes([first]) + rl + body


def dcmd_dup(port, group, edge, device, name, dtype, value, ts):
    """The DCMD published twice as MQTT 3.1.1 packets written by hand (OASIS
    MQTT 3.1.1 3.1, 3.3): PUBLISH QoS 1 packet id 7, then the same packet with
    DUP set, as a publisher resends it when its PUBACK was lost. The broker
    forwards both (QoS 1 is at least once)."""
    import socket
    raw = dcmd_payload(name, dtype, value, None if ts == "none" else ts)
    if ts == "none":  # no payload or metric timestamp at all
        p = pb.Payload.FromString(raw)
        p.ClearField("timestamp")
        for m in p.metrics:
            m.ClearField("timestamp")
        raw = p.SerializeToString()
    topic = "spBv1.0/%s/DCMD/%s/%s" % (group, edge, device)
    s = socket.create_connection(("127.0.0.1", int(port)), 5)
    s.settimeout(5)
    s.sendall(mqtt_packet(0x10, mqtt_string("MQTT") + bytes([4, 2]) + (30).to_bytes(2, "big") +
                          mqtt_string("dup%d" % time.time_ns())))
    if s.recv(4)[:1] != b"\x20":
        sys.exit("dcmd-dup: no CONNACK")
    body = mqtt_string(topic) + (7).to_bytes(2, "big") + raw
    s.sendall(mqtt_packet(0x32, body))          # PUBLISH, QoS 1
    s.sendall(mqtt_packet(0x3A, body))          # the same, DUP set
    got = b""
    while len(got) < 8:                         # two PUBACKs of 4 bytes
        c = s.recv(8 - len(got))
        if not c:
            sys.exit("dcmd-dup: the broker closed")
        got += c
    s.sendall(bytes([0xE0, 0]))                 # DISCONNECT
    s.close()


def state(port, host, online, ts=None):
    body = json.dumps({"online": online == "online", "timestamp": int(ts) if ts else spb.get_current_timestamp()})
    publish(port, "spBv1.0/STATE/%s" % host, body.encode(), retain=True)


def load(path):
    with open(path) as f:
        return [json.loads(line) for line in f if line.strip()]


def check(path, what):
    """Print one line per failed rule; exit 1 if any."""
    recs = [r for r in load(path) if r["type"] != "STATE"]
    fails = []
    for r in recs:
        if "error" in r and r["type"] not in ("NCMD", "DCMD"):  # the node's messages; commands are the test's
            fails.append("%s: pysparkplug could not decode it: %s" % (r["topic"], r["error"]))
    # seq: NBIRTH is 0, then +1 mod 256 over every message of the node (NDEATH has none)
    expect = None
    for r in recs:
        if r["type"] == "NBIRTH":
            if r.get("seq") != 0:
                fails.append("NBIRTH seq %s, not 0" % r.get("seq"))
            expect = 1
        elif r["type"] in ("DBIRTH", "DDATA", "DDEATH", "NDATA"):
            if expect is None:
                fails.append("%s before any NBIRTH" % r["topic"])
            elif r.get("seq") != expect:
                fails.append("%s seq %s, expected %s" % (r["topic"], r.get("seq"), expect))
            expect = (r.get("seq", 0) + 1) % 256
    # every DBIRTH and DDATA metric carries its time (the read's)
    for r in recs:
        if r["type"] in ("DBIRTH", "DDATA"):
            for m in r["metrics"]:
                if not m.get("timestamp"):
                    fails.append("%s %s: metric %s without a timestamp" % (r["type"], r["device"], m["name"]))
    # every DDATA metric was in its device's last DBIRTH with the same datatype
    births = {}
    for r in recs:
        if r["type"] == "DBIRTH":
            births[r["device"]] = {m["name"]: m["datatype"] for m in r["metrics"]}
        elif r["type"] == "DDATA":
            b = births.get(r["device"])
            if b is None:
                fails.append("DDATA of %s before its DBIRTH" % r["device"])
                continue
            for m in r["metrics"]:
                if b.get(m["name"]) != m["datatype"]:
                    fails.append("DDATA %s %s %s not in DBIRTH (%s)" % (r["device"], m["name"], m["datatype"],
                                                                       b.get(m["name"])))
    # NBIRTH's bdSeq equals the will's (the NDEATH that follows it)
    for i, r in enumerate(recs):
        if r["type"] == "NBIRTH":
            bd = [m["value"] for m in r["metrics"] if m["name"] == "bdSeq"]
            rb = [m for m in r["metrics"] if m["name"] == "Node Control/Rebirth"]
            if not rb or rb[0]["datatype"] != "BOOLEAN" or rb[0]["value"] is not False or rb[0]["alias"]:
                fails.append("NBIRTH: Node Control/Rebirth not Boolean false without alias")
            nxt = [d for d in recs[i + 1:] if d["type"] in ("NDEATH", "NBIRTH")]
            if nxt and nxt[0]["type"] == "NDEATH" and bd and nxt[0]["bdseq"] != bd[0]:
                fails.append("NBIRTH bdSeq %s, NDEATH bdSeq %s" % (bd[0], nxt[0]["bdseq"]))
    for f in fails[:20]:
        print(f)
    sys.exit(1 if fails else 0)


def main():
    a = sys.argv[1:]
    if a[0] == "record":
        record(a[1], a[2])
    elif a[0] == "ncmd":
        ncmd(*a[1:])
    elif a[0] == "dcmd":
        dcmd(*a[1:])
    elif a[0] == "dcmd-dup":
        dcmd_dup(*a[1:])
    elif a[0] == "state":
        state(*a[1:])
    elif a[0] == "check":
        check(a[1], a[2:])
    elif a[0] == "alias":
        print([m["alias"] for r in load(a[1]) if r["type"] == "DBIRTH" for m in r["metrics"] if m["name"] == a[2]][-1])
    elif a[0] == "has":
        R = load(a[1])[int(a[2]):]  # noqa: N806 - the name the expressions use
        sys.exit(0 if eval(a[3], {"R": R}) else 1)


if __name__ == "__main__":
    main()
