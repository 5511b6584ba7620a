#!/usr/bin/env python3
"""Writes the hand-made seeds of the `cache_entry` fuzz target.

Each seed is a mode byte (low two bits: 0 the entry file as found, 1 a body under an
intact header, 2 a body stored through the cache; the rest: a size limit of 8 bytes a
step, 0 none) and its bytes: an intact entry of the target's key holding a SPIR-V body,
the same damaged, a radiance body of two texels and a forged one (a NaN texel), a
foreign magic, a body past a small size limit, an empty body. Run from anywhere:
`python3 fuzz/seeds/cache_entry/generate.py`.
"""
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
MAGIC = b"FUZZCA01"
PRIME = 0x0000_0100_0000_01B3
MASK = (1 << 64) - 1


class Digest:
    """combustion_disk_cache::Digest: two FNV-1a 64 hashes, each part's length first."""

    def __init__(self):
        self.low, self.high = 0xCBF2_9CE4_8422_2325, 0x6C62_272E_07BB_0142

    def _bytes(self, data):
        for byte in data:
            self.low = ((self.low ^ byte) * PRIME) & MASK
            rotated = ((byte << 3) | (byte >> 5)) & 0xFF
            self.high = ((self.high ^ rotated) * PRIME) & MASK

    def part(self, data):
        self._bytes(struct.pack("<Q", len(data)))
        self._bytes(data)
        return self

    def to_bytes(self):
        return struct.pack("<QQ", self.low, self.high)


def key(mode):
    return Digest().part(b"fuzz").part(bytes([mode])).to_bytes()


def entry(mode, body, magic=MAGIC):
    checksum = Digest().part(body).to_bytes()[:8]
    return magic + key(mode) + checksum + body


SPIRV = struct.pack("<5I", 0x07230203, 0x00010600, 0, 8, 0)
RADIANCE = struct.pack("<8f", 0.5, 1.0, 2.0, 1.0, 0.0, 3.0, 1e30, 1.0)
FORGED = struct.pack("<8f", 0.5, float("nan"), 2.0, 1.0, 0.0, 3.0, 1.0, 1.0)

SEEDS = {
    "intact-spirv": bytes([0]) + entry(0, SPIRV),
    "damaged-spirv": bytes([0]) + entry(0, SPIRV)[:-1] + b"\x01",
    "foreign-magic": bytes([0]) + entry(0, SPIRV, b"CMBSPV01"),
    "short-header": bytes([0]) + entry(0, b"")[:20],
    "radiance-body": bytes([1]) + RADIANCE,
    "forged-radiance": bytes([1]) + FORGED,
    "spirv-body-past-a-limit": bytes([1 | (2 << 2)]) + SPIRV,
    "stored-body": bytes([2]) + SPIRV,
    "empty-body": bytes([1]),
}

for name, data in SEEDS.items():
    with open(os.path.join(HERE, name), "wb") as f:
        f.write(data)
