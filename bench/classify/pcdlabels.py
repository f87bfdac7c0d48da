"""Majority truth label of a candidate's above-ground points (evaluation only; classify never
reads labels). Reads canopy's binary PCD (DATA binary)."""
import struct


def read_pcd(path, fields_wanted):
    with open(path, "rb") as f:
        data = f.read()
    head = {}
    pos = 0
    while True:
        end = data.index(b"\n", pos)
        line = data[pos:end].decode("ascii", "replace").strip()
        pos = end + 1
        if not line or line.startswith("#"):
            continue
        key, *vals = line.split()
        head[key] = vals
        if key == "DATA":
            break
    if head["DATA"][0] != "binary":
        raise ValueError(path + ": only DATA binary")
    names, sizes, types, counts = head["FIELDS"], list(map(int, head["SIZE"])), head["TYPE"], list(map(int, head["COUNT"]))
    n = int(head["POINTS"][0])
    fmt = "<"
    for s, t, c in zip(sizes, types, counts):
        code = {("F", 4): "f", ("F", 8): "d", ("U", 1): "B", ("U", 2): "H", ("U", 4): "I", ("I", 1): "b", ("I", 2): "h", ("I", 4): "i"}[(t, s)]
        fmt += code * c
    rec = struct.calcsize(fmt)
    cols = {name: [] for name in fields_wanted}
    idx = {name: names.index(name) for name in fields_wanted if name in names}
    for i in range(n):
        row = struct.unpack_from(fmt, data, pos + i * rec)
        for name, k in idx.items():
            cols[name].append(row[k])
    return cols


def majority_label(path, cut=0.3):
    c = read_pcd(path, ["z", "label"])
    counts = {}
    for z, l in zip(c["z"], c["label"]):
        if z >= cut:
            counts[l] = counts.get(l, 0) + 1
    if not counts:
        return None
    return max(counts.items(), key=lambda kv: kv[1])[0]
