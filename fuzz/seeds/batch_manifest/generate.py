#!/usr/bin/env python3
"""Writes the hand-made seeds of the `batch_manifest` fuzz target.

Each seed is a batch manifest, then (after a NUL byte each) up to four shards'
results.json texts: a manifest of every kind of key (defaults, criteria, outputs,
render options by their long names), with the results of its two shards; manifests
refused for a duplicate key, a long value, a scene file not found, criteria of the
wrong kind, an output named twice, names equal without case, and scene and
environment values longer than any path; shards of two manifests, a shard index of 20
digits, a shard given twice, a job in two shards and a name holding U+FFFF. Run from anywhere: `python3 fuzz/seeds/batch_manifest/generate.py`.
"""
import json
import os

HERE = os.path.dirname(os.path.abspath(__file__))

MANIFEST = {
    "$schema": "../../docs/batch-manifest.schema.json",
    "criteria": "mean-flip <= 0.01",
    "hdr_criteria": "max-relative-diff 1e-3 on at most 1% of pixels",
    "defaults": {"width": 64, "height": 36, "scene": "builtin:spheres"},
    "jobs": [
        {"name": "spheres"},
        {"name": "grid", "scene": "builtin:grid-7x7", "light-rig": True, "shadows": True,
         "fresnel": "schlick", "camera": "orbit:30,20", "ev": -1,
         "outputs": ["exr", "png"], "error": True},
        {"name": "studio", "scene": "builtin:spheres-studio", "environment": "studio",
         "criteria": "max-channel-diff 2/255 on at most 0.5% of pixels"},
    ],
}


def digest(text):
    """combustion::cli::manifest::text_digest: FNV-1a 64 of the text's bytes, in hex."""
    value = 0xCBF2_9CE4_8422_2325
    for byte in text.encode():
        value = ((value ^ byte) * 0x0000_0100_0000_01B3) & ((1 << 64) - 1)
    return f"{value:016x}"


def job(index, name):
    return {"index": index, "name": name, "scene": "builtin:spheres", "status": "passed",
            "message": None, "seconds": 0.5,
            "outputs": [{"kind": "png", "file": f"{name}.png", "mean_flip": 0.001}],
            "physics_error": None}


def results(manifest_text, index, count, jobs, name="m"):
    return json.dumps({"manifest": name, "manifest_digest": digest(manifest_text),
                       "shard": {"index": index, "count": count}, "seconds": 2.0,
                       "jobs": jobs}, indent=2)


def write(name, parts):
    with open(os.path.join(HERE, name), "wb") as f:
        f.write(b"\0".join(p.encode() for p in parts))


def main():
    text = json.dumps(MANIFEST, indent=2)
    # Sorted by name, spheres/grid/studio deal out as grid, studio to shard 1; spheres to 2.
    shard1 = results(text, 1, 2, [job(1, "grid"), job(2, "studio")])
    shard2 = results(text, 2, 2, [job(0, "spheres")])
    write("manifest-and-its-shards", [text, shard1, shard2])
    write("manifest-alone", [text])
    write("duplicate-key", ['{"jobs": [{"name": "a", "scene": "builtin:spheres"}], '
                            '"jobs": [{"name": "b", "scene": "builtin:spheres"}]}'])
    write("long-value", [json.dumps({"jobs": [{"name": "a", "scene": "builtin:spheres",
                                               "camera": "x" * 5000}]})])
    write("scene-file-not-found", [json.dumps({"jobs": [{"name": "a", "scene": "a.gltf"}]})])
    # The target's first find: a scene value of 3,000 bytes echoed whole as a path.
    write("scene-longer-than-any-path",
          [json.dumps({"jobs": [{"name": "a", "scene": "x" * 8000 + ".gltf"}]})])
    write("environment-longer-than-any-path", [json.dumps(
        {"jobs": [{"name": "a", "scene": "builtin:spheres", "environment": "x" * 8000 + ".hdr"}]})])
    write("criteria-of-the-wrong-kind", [json.dumps(
        {"hdr_criteria": "max-channel-diff 1/255 on at most 0% of pixels",
         "jobs": [{"name": "a", "scene": "builtin:spheres"}]})])
    write("output-named-twice", [json.dumps(
        {"jobs": [{"name": "a", "scene": "builtin:spheres", "outputs": ["png", "png"]}]})])
    write("names-equal-without-case", [json.dumps(
        {"jobs": [{"name": "Ab", "scene": "builtin:spheres"},
                  {"name": "aB", "scene": "builtin:spheres"}]})])
    other = results(text + " ", 2, 2, [job(0, "spheres")])
    write("shards-of-two-manifests", ["", shard1, other])
    write("shard-index-of-20-digits",
          ["", results(text, 18446744073709551615, 2, [job(0, "spheres")])])
    write("shard-given-twice", ["", shard1, shard1])
    write("job-in-two-shards", ["", results(text, 1, 2, [job(0, "spheres")]),
                                results(text, 2, 2, [job(0, "spheres")])])
    write("name-holding-uffff", ["", results(text, 1, 1, [job(0, "a\uffffb")])])


if __name__ == "__main__":
    main()
