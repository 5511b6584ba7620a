#!/usr/bin/env python3
"""Writes a textured Khronos sample model with a camera and lights of its own, for the
side by side with Bevy (scripts/side_by_side.sh): both renderers load the same file and
see it through its camera, lit by its lights (KHR_lights_punctual), nothing else.

    textured_twin.py MODEL.gltf OUT_DIR

The model's glTF and the files it names are copied into OUT_DIR (outside the
repository: the sample models are not copied into it); the copy gets a perspective
camera framing the model's box from +Z (its height filling 5/6 of a 1280×720 view) and
two point lights, key and fill, before it.
"""
import json
import math
import os
import shutil
import sys


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: textured_twin.py MODEL.gltf OUT_DIR")
    source, out = sys.argv[1], sys.argv[2]
    with open(source) as f:
        root = json.load(f)
    folder = os.path.dirname(os.path.abspath(source))
    os.makedirs(out, exist_ok=True)
    for entry in root.get("buffers", []) + root.get("images", []):
        uri = entry.get("uri", "")
        if uri and not uri.startswith("data:"):
            target = os.path.join(out, uri)
            os.makedirs(os.path.dirname(target), exist_ok=True)
            shutil.copyfile(os.path.join(folder, uri), target)
    # The box of every POSITION accessor (the sample models place their meshes near the
    # origin; rotations about +Y, as Avocado's, leave the height and depth's extent).
    lo, hi = [math.inf] * 3, [-math.inf] * 3
    for mesh in root["meshes"]:
        for primitive in mesh["primitives"]:
            accessor = root["accessors"][primitive["attributes"]["POSITION"]]
            lo = [min(a, b) for a, b in zip(lo, accessor["min"])]
            hi = [max(a, b) for a, b in zip(hi, accessor["max"])]
    centre = [(a + b) / 2 for a, b in zip(lo, hi)]
    height = hi[1] - lo[1]
    radius = max(hi[0] - lo[0], hi[2] - lo[2]) / 2
    yfov = 0.5
    distance = radius + (height / 2) / (5 / 6) / math.tan(yfov / 2)
    eye = [centre[0], centre[1], centre[2] + distance]
    root.setdefault("cameras", []).insert(0, {
        "type": "perspective",
        "perspective": {"yfov": yfov, "aspectRatio": 16 / 9, "znear": distance / 100, "zfar": distance * 10},
    })
    # Cameras after the first keep their indices, shifted by one.
    for node in root["nodes"]:
        if "camera" in node:
            node["camera"] += 1
    lights = [
        {"type": "point", "color": [1.0, 0.96, 0.9], "intensity": 3.0 * distance ** 2, "name": "key"},
        {"type": "point", "color": [0.85, 0.9, 1.0], "intensity": 1.0 * distance ** 2, "name": "fill"},
    ]
    extensions = root.setdefault("extensions", {})
    extensions["KHR_lights_punctual"] = {"lights": lights}
    used = root.setdefault("extensionsUsed", [])
    if "KHR_lights_punctual" not in used:
        used.append("KHR_lights_punctual")
    added = [
        {"name": "twin camera", "camera": 0, "translation": eye},
        {"name": "key light", "translation": [centre[0] + distance * 0.8, centre[1] + distance, centre[2] + distance],
         "extensions": {"KHR_lights_punctual": {"light": 0}}},
        {"name": "fill light", "translation": [centre[0] - distance, centre[1], centre[2] + distance * 0.6],
         "extensions": {"KHR_lights_punctual": {"light": 1}}},
    ]
    first = len(root["nodes"])
    root["nodes"].extend(added)
    scene = root["scenes"][root.get("scene", 0)]
    scene["nodes"] = list(range(first, first + len(added))) + scene["nodes"]
    name = os.path.basename(source)
    with open(os.path.join(out, name), "w") as f:
        json.dump(root, f)
    print(os.path.join(out, name))


if __name__ == "__main__":
    main()
