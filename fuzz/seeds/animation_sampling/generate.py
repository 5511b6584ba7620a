#!/usr/bin/env python3
"""Writes the hand-made seeds of the `animation_sampling` fuzz target.

Each seed is two little-endian f32 times (the times the target samples besides the
animation's start, middle and end) followed by a small glTF file (JSON, buffers as
data: URIs) with one kind of animation: translation, rotation and scale keys under each
interpolation, morph weights, a skin's joints, and the hard cases of rotation keys (from
q to -q, all zero). Run from anywhere: `python3 fuzz/seeds/animation_sampling/generate.py`.
"""
import base64
import json
import math
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))


def data_uri(data):
    return "data:application/octet-stream;base64," + base64.b64encode(data).decode()


class Buffer:
    """One buffer of views and accessors, appended to in order."""

    def __init__(self):
        self.data = b""
        self.views = []
        self.accessors = []

    def add(self, floats, kind, count, component=5126, fmt="f", extra=None):
        raw = struct.pack("<%d%s" % (len(floats), fmt), *floats)
        raw += b"\0" * ((4 - len(raw) % 4) % 4)
        self.views.append({"buffer": 0, "byteOffset": len(self.data), "byteLength": len(raw)})
        self.data += raw
        accessor = {"bufferView": len(self.views) - 1, "componentType": component,
                    "count": count, "type": kind}
        accessor.update(extra or {})
        self.accessors.append(accessor)
        return len(self.accessors) - 1


def triangle(buf, morph=False, skinned=False):
    positions = [0, 0, 0, 1, 0, 0, 0, 1, 0]
    attributes = {
        "POSITION": buf.add(positions, "VEC3", 3, extra={"min": [0, 0, 0], "max": [1, 1, 0]}),
        "NORMAL": buf.add([0, 0, 1] * 3, "VEC3", 3),
    }
    primitive = {"attributes": attributes}
    if morph:
        target = buf.add([0, 0, 0.5, 0.5, 0, 0, 0, 0.5, 0], "VEC3", 3,
                         extra={"min": [0, 0, 0], "max": [0.5, 0.5, 0.5]})
        primitive["targets"] = [{"POSITION": target}]
    if skinned:
        attributes["JOINTS_0"] = buf.add([0, 1, 0, 0] * 3, "VEC4", 3, component=5121, fmt="B")
        attributes["WEIGHTS_0"] = buf.add([0.5, 0.5, 0, 0] * 3, "VEC4", 3)
    return primitive


def gltf(buf, nodes, meshes, animations, skins=None, roots=(0,)):
    g = {
        "asset": {"version": "2.0", "generator": "fuzz/seeds/animation_sampling/generate.py"},
        "scene": 0,
        "scenes": [{"nodes": list(roots)}],
        "nodes": nodes,
        "meshes": meshes,
        "animations": animations,
        "accessors": buf.accessors,
        "bufferViews": buf.views,
        "buffers": [{"byteLength": len(buf.data), "uri": data_uri(buf.data)}],
    }
    if skins:
        g["skins"] = skins
    return g


def channel_animation(buf, path, keys, values, kind, interpolation="LINEAR", node=0):
    times = buf.add(keys, "SCALAR", len(keys), extra={"min": [min(keys)], "max": [max(keys)]})
    width = {"VEC3": 3, "VEC4": 4, "SCALAR": 1}[kind]
    count = len(values) // width
    output = buf.add(values, kind, count)
    return {"channels": [{"sampler": 0, "target": {"node": node, "path": path}}],
            "samplers": [{"input": times, "output": output, "interpolation": interpolation}]}


seeds = {}


def seed(name, g, times=(0.25, 7.0)):
    seeds[name] = struct.pack("<2f", *times) + json.dumps(g, separators=(",", ":")).encode()


def node_channel(name, path, keys, values, kind, interpolation="LINEAR", times=(0.25, 7.0)):
    buf = Buffer()
    mesh = {"primitives": [triangle(buf)]}
    animation = channel_animation(buf, path, keys, values, kind, interpolation)
    seed(name, gltf(buf, [{"mesh": 0}], [mesh], [animation]), times)


s = math.sqrt(0.5)
node_channel("translation-linear", "translation", [0, 1], [0, 0, 0, 1, 2, 3], "VEC3")
node_channel("translation-step", "translation", [0, 0.5, 1], [0, 0, 0, 1, 0, 0, 0, 1, 0], "VEC3", "STEP")
node_channel("translation-cubic", "translation", [0, 1],
             [0, 0, 0, 0, 0, 0, 1, 0, 0, 1, 0, 0, 2, 0, 0, 0, 0, 0], "VEC3", "CUBICSPLINE")
node_channel("rotation-linear", "rotation", [0, 1], [0, 0, 0, 1, 0, s, 0, s], "VEC4")
node_channel("rotation-cubic", "rotation", [0, 1, 2],
             [0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0,
              0, 0, 0, 0, 0, s, 0, s, 0, 0, 0, 0,
              0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0], "VEC4", "CUBICSPLINE")
# From q to -q (the same rotation, the long way in 4D), and keys of all zeros.
node_channel("rotation-cubic-q-to-minus-q", "rotation", [0, 1],
             [0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0,
              0, 0, 0, 0, 0, 0, 0, -1, 0, 0, 0, 0], "VEC4", "CUBICSPLINE", times=(0.5, 0.5))
node_channel("rotation-all-zero", "rotation", [0, 1], [0, 0, 0, 0, 0, 0, 0, 0], "VEC4", times=(0.5, -3.0))
node_channel("scale-linear", "scale", [0, 2], [1, 1, 1, -1, 1, 1], "VEC3", times=(1.0, 1e30))
node_channel("scale-huge", "scale", [0, 1], [1, 1, 1, 3e38, 3e38, 3e38], "VEC3", times=(0.5, 1.0))
node_channel("one-key", "translation", [0.5], [1, 1, 1], "VEC3", times=(float("nan"), float("inf")))

# Morph weights.
buf = Buffer()
mesh = {"primitives": [triangle(buf, morph=True)], "weights": [0.0]}
animation = channel_animation(buf, "weights", [0, 1], [0.0, 1.0], "SCALAR")
seed("morph-weights", gltf(buf, [{"mesh": 0}], [mesh], [animation]), (0.5, -1.0))

# A skin of two joints, the second rotated.
buf = Buffer()
mesh = {"primitives": [triangle(buf, skinned=True)]}
inverse = buf.add([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1] * 2, "MAT4", 2)
animation = channel_animation(buf, "rotation", [0, 1], [0, 0, 0, 1, 0, 0, s, s], "VEC4", node=2)
nodes = [{"mesh": 0, "skin": 0}, {"children": [2]}, {"translation": [0, 1, 0]}]
skins = [{"joints": [1, 2], "inverseBindMatrices": inverse}]
seed("skin-two-joints", gltf(buf, nodes, [mesh], [animation], skins, roots=(0, 1)), (0.5, 2.0))

for old in os.listdir(HERE):
    if old.endswith(".seed"):
        os.remove(os.path.join(HERE, old))
for name, data in sorted(seeds.items()):
    with open(os.path.join(HERE, name + ".seed"), "wb") as f:
        f.write(data)
print("wrote %d seeds" % len(seeds))
