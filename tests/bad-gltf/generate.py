#!/usr/bin/env python3
"""Writes the corpus of bad glTF files, one defect per file, named for it.

Run from anywhere: `python3 tests/bad-gltf/generate.py`. Each file is a small valid
glTF (one triangle, buffers as data: URIs) with one thing broken. The expected error of
each is asserted by crates/scene/tests/bad_gltf.rs; the fuzzer uses them as seeds.
"""
import base64
import copy
import json
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))


def data_uri(data, mime="application/octet-stream"):
    return "data:%s;base64,%s" % (mime, base64.b64encode(data).decode())


def triangle(positions=None, indices=(0, 1, 2), normals=True):
    positions = positions or [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0)]
    pos = b"".join(struct.pack("<3f", *p) for p in positions)
    nor = b"".join(struct.pack("<3f", 0.0, 0.0, 1.0) for _ in positions) if normals else b""
    idx = b"".join(struct.pack("<H", i) for i in indices)
    idx += b"\0" * ((4 - len(idx) % 4) % 4)
    data = pos + nor + idx
    views = [
        {"buffer": 0, "byteOffset": 0, "byteLength": len(pos)},
        {"buffer": 0, "byteOffset": len(pos), "byteLength": len(nor)},
        {"buffer": 0, "byteOffset": len(pos) + len(nor), "byteLength": len(indices) * 2},
    ]
    accessors = [
        {"bufferView": 0, "componentType": 5126, "count": len(positions), "type": "VEC3",
         "min": [0, 0, 0], "max": [1, 1, 0]},
        {"bufferView": 1, "componentType": 5126, "count": len(positions), "type": "VEC3"},
        {"bufferView": 2, "componentType": 5123, "count": len(indices), "type": "SCALAR"},
    ]
    attributes = {"POSITION": 0}
    if normals:
        attributes["NORMAL"] = 1
    return {
        "asset": {"version": "2.0", "generator": "tests/bad-gltf/generate.py"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": attributes, "indices": 2, "material": 0}]}],
        "materials": [{"name": "grey", "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1]}}],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(data), "uri": data_uri(data)}],
    }


def png(width, height, rgba=None, idat=None):
    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))
    ihdr = struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0)
    if idat is None:
        raw = b"".join(b"\0" + bytes(rgba[y * width * 4:(y + 1) * width * 4]) for y in range(height))
        idat = zlib.compress(raw)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", idat) + chunk(b"IEND", b"")


def textured(image_bytes, mime="image/png"):
    g = triangle()
    g["images"] = [{"name": "texture", "uri": data_uri(image_bytes, mime)}]
    g["textures"] = [{"source": 0}]
    g["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {"index": 0}
    return g


def glb(json_bytes, bin_bytes=None, version=2, length=None, first_chunk=b"JSON", pad=True):
    if pad:
        json_bytes += b" " * ((4 - len(json_bytes) % 4) % 4)
    body = struct.pack("<I", len(json_bytes)) + first_chunk + json_bytes
    if bin_bytes is not None:
        bin_bytes += b"\0" * ((4 - len(bin_bytes) % 4) % 4)
        body += struct.pack("<I", len(bin_bytes)) + b"BIN\0" + bin_bytes
    total = 12 + len(body)
    return b"glTF" + struct.pack("<II", version, length if length is not None else total) + body


def dump(g):
    return json.dumps(g, indent=1).encode()


files = {}


def bad(name, g):
    files[name] = g if isinstance(g, bytes) else dump(g)


ok = dump(triangle())
bad("empty-file.gltf", b"")
bad("truncated-json.gltf", ok[: len(ok) // 2])
bad("garbled-json.gltf", b'{"asset": {"version": "2.0"}, "nodes": [}, ]]')
bad("not-gltf-2.gltf", dict(triangle(), asset={"version": "1.0"}))

bin_glb = glb(json.dumps({"asset": {"version": "2.0"}, "buffers": [{"byteLength": 4}]}).encode(), b"\1\2\3\4")
bad("truncated.glb", bin_glb[: len(bin_glb) - 6])
bad("glb-version-1.glb", glb(b'{"asset":{"version":"2.0"}}', version=1))
bad("glb-first-chunk-not-json.glb", glb(b'{"asset":{"version":"2.0"}}', first_chunk=b"XXXX"))
g = triangle()
g["buffers"][0] = {"byteLength": g["buffers"][0]["byteLength"]}
bad("glb-missing-bin-chunk.glb", glb(json.dumps(g).encode()))
# A JSON chunk of 29 bytes, unpadded, before the BIN chunk.
bad("glb-unpadded-json-chunk.glb", glb(b'{"asset":{"version":"2.0"}}  ', b"\1\2\3\4", pad=False))

g = triangle(); g["buffers"][0]["uri"] = "missing-buffer.bin"
bad("missing-buffer-file.gltf", g)
g = triangle(); g["buffers"][0]["byteLength"] += 100
bad("short-buffer.gltf", g)
g = triangle(); g["bufferViews"][2]["byteOffset"] += 64
bad("buffer-view-out-of-range.gltf", g)
g = triangle(); g["accessors"][0]["count"] = 30; g["accessors"][1]["count"] = 30
bad("accessor-out-of-range.gltf", g)
bad("index-out-of-range.gltf", triangle(indices=(0, 1, 7)))
g = triangle(); g["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 9
bad("accessor-index-missing.gltf", g)
g = triangle(); g["accessors"][0]["type"] = "VEC2"
bad("wrong-accessor-type.gltf", g)
g = triangle(); del g["meshes"][0]["primitives"][0]["attributes"]["POSITION"]
bad("missing-position.gltf", g)
g = triangle(); g["accessors"][1]["count"] = 2
bad("mismatched-attribute-counts.gltf", g)
bad("nan-position.gltf", triangle(positions=[(0, 0, 0), (float("nan"), 0, 0), (0, 1, 0)]))
bad("infinite-position.gltf", triangle(positions=[(0, 0, 0), (1, 0, 0), (0, float("inf"), 0)]))
bad("all-degenerate-triangles.gltf", triangle(positions=[(0, 0, 0), (1, 1, 1), (2, 2, 2)]))
# Points and lines (modes 0-3) are checked as triangles are.
g = triangle(indices=(0, 1, 7)); g["meshes"][0]["primitives"][0]["mode"] = 2
bad("line-loop-index-out-of-range.gltf", g)
g = triangle(indices=(0,)); g["meshes"][0]["primitives"][0]["mode"] = 3
bad("line-strip-of-one-index.gltf", g)
g = triangle(positions=[(0, 0, 0), (float("nan"), 0, 0), (0, 1, 0)]); g["meshes"][0]["primitives"][0]["mode"] = 0
bad("nan-point.gltf", g)

bad("undecodable-png.gltf", textured(b"\x89PNG\r\n\x1a\n" + b"garbage" * 10))
bad("unsupported-image-format.gltf", textured(b"GIF89a\x01\x00\x01\x00\x00\x00\x00;", "image/gif"))
bad("huge-image.gltf", textured(png(20000, 20000, idat=zlib.compress(b"\0" * 64))))
bad("image-over-limit.gltf", textured(png(16, 16, rgba=[200] * (16 * 16 * 4))))

for name, uri in [
    ("uri-leaves-folder.gltf", "../outside.bin"),
    ("uri-absolute-path.gltf", "/etc/hostname"),
    ("uri-file-scheme.gltf", "file:///etc/hostname"),
    ("uri-http-scheme.gltf", "https://example.com/triangle.bin"),
    ("uri-bad-base64.gltf", "data:application/octet-stream;base64,AAAA*AAA"),
]:
    g = triangle(); g["buffers"][0]["uri"] = uri
    bad(name, g)

g = triangle(); g["extensionsUsed"] = g["extensionsRequired"] = ["KHR_draco_mesh_compression"]
bad("unsupported-required-extension.gltf", g)
g = triangle(); g["nodes"] = [{"mesh": 0, "children": [1]}, {"children": [0]}]
bad("node-cycle.gltf", g)
g = triangle()
g["extensionsUsed"] = ["COMBUSTION_materials_optics"]
g["materials"][0]["extensions"] = {"COMBUSTION_materials_optics": {"conductor": {"metal": "unobtainium"}}}
bad("optics-unknown-metal.gltf", g)
g = triangle()
g["extensionsUsed"] = ["COMBUSTION_materials_optics"]
g["materials"][0]["extensions"] = {"COMBUSTION_materials_optics": {"conductor": {"spectrum": "../../assets/spectra/Au_McPeak2015.csv"}}}
bad("optics-spectrum-outside-folder.gltf", g)
g = triangle()
g["extensionsUsed"] = ["KHR_materials_anisotropy"]
g["materials"][0]["extensions"] = {"KHR_materials_anisotropy": {"anisotropyStrength": "high"}}
bad("anisotropy-strength-not-a-number.gltf", g)
g = triangle()
g["cameras"] = [{"type": "perspective", "perspective": {"yfov": 0.0, "znear": 0.1}}]
g["nodes"].append({"camera": 0}); g["scenes"][0]["nodes"].append(1)
bad("camera-zero-fov.gltf", g)
g = triangle()
g["extensionsUsed"] = ["KHR_lights_punctual"]
g["extensions"] = {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": -5.0}]}}
g["nodes"].append({"extensions": {"KHR_lights_punctual": {"light": 0}}}); g["scenes"][0]["nodes"].append(1)
bad("light-negative-intensity.gltf", g)
g = triangle(positions=[(0.0, 0.0, 0.0), (1e10, 0.0, 0.0), (0.0, 1e10, 0.0)])
g["nodes"] = [{"mesh": 0, "name": "huge", "scale": [1e30, 1e30, 1e30]}]
bad("object-overflows-f32.gltf", g)

# An animation whose accessors declare 2^62 keys: the import budget must refuse it, not
# overflow multiplying the count.
g = triangle()
g["accessors"].append({"bufferView": 0, "componentType": 5126, "count": 2 ** 62, "type": "SCALAR"})
g["accessors"].append({"bufferView": 0, "componentType": 5126, "count": 2 ** 62, "type": "VEC3"})
g["animations"] = [{"channels": [{"sampler": 0, "target": {"node": 0, "path": "translation"}}],
                    "samplers": [{"input": 3, "output": 4}]}]
bad("animation-key-count-overflows.gltf", g)

for old in os.listdir(HERE):
    if old.endswith((".gltf", ".glb")):
        os.remove(os.path.join(HERE, old))
for name, data in sorted(files.items()):
    with open(os.path.join(HERE, name), "wb") as f:
        f.write(data)
print("wrote %d files" % len(files))
