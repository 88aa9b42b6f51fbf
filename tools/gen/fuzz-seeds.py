#!/usr/bin/env python3
"""Writes the binary seeds of the fuzz targets (tools/fuzz.sh) into OUT_DIR/<target>/:
  klv/   MISB ST 0601 packets: a small one with a valid checksum, one with a nested ST 0102
         security set and a bad checksum, and a stream of two packets with garbage between
  gltf/  a .glb: one textured triangle whose PNG lies in a bufferView of the binary chunk
usage: fuzz-seeds.py OUT_DIR"""
import json, os, struct, sys, zlib

KEY = bytes([0x06, 0x0E, 0x2B, 0x34, 0x02, 0x0B, 0x01, 0x01, 0x0E, 0x01, 0x03, 0x01, 0x01, 0x00, 0x00, 0x00])


def ber(n):
    if n < 128:
        return bytes([n])
    b = n.to_bytes((n.bit_length() + 7) // 8, 'big')
    return bytes([0x80 | len(b)]) + b


def tlv(tag, value):
    return bytes([tag]) + ber(len(value)) + value


def packet(items, good_checksum=True):
    body = b''.join(tlv(t, v) for t, v in items)
    body += bytes([1, 2])   # checksum tag and length; the sum covers them
    whole = KEY + ber(len(body) + 2) + body
    s = 0
    for i, b in enumerate(whole):
        s = (s + (b << (8 * ((i + 1) % 2)))) & 0xFFFF
    if not good_checksum:
        s ^= 0x5A5A
    return whole + struct.pack('>H', s)


def angle(value, lo, hi, bits=32):
    # ST 0601 maps [lo, hi] onto a signed or unsigned integer range.
    span = (1 << bits) - 2 if lo < 0 else (1 << bits) - 1
    if lo < 0:
        return struct.pack('>i', int(round(value / (hi / ((1 << (bits - 1)) - 1)))))
    return struct.pack('>I', int(round((value - lo) / (hi - lo) * span)))


def klv_seeds(out):
    os.makedirs(out, exist_ok=True)
    base = [(2, struct.pack('>Q', 1231798102000000)), (65, bytes([17])), (3, b'MISSION01'),
            (5, struct.pack('>H', 28000)), (13, angle(60.1768, -90, 90)), (14, angle(128.4268, -180, 180)),
            (15, struct.pack('>H', 30000)), (16, struct.pack('>H', 2000)), (17, struct.pack('>H', 1100)),
            (18, struct.pack('>I', 1 << 30)), (19, struct.pack('>i', -(1 << 29))), (21, struct.pack('>I', 5000000)),
            (23, angle(60.17, -90, 90)), (24, angle(128.43, -180, 180))]
    small = packet(base)
    with open(os.path.join(out, 'packet.bin'), 'wb') as f:
        f.write(small)
    security = tlv(1, bytes([1])) + tlv(2, bytes([1])) + tlv(3, b'//US') + tlv(22, struct.pack('>H', 5))
    nested = packet(base + [(48, security), (94, bytes([0x06, 0x0E, 0x2B, 0x34]))], good_checksum=False)
    with open(os.path.join(out, 'nested-bad-checksum.bin'), 'wb') as f:
        f.write(nested)
    with open(os.path.join(out, 'stream.bin'), 'wb') as f:
        f.write(small + b'\x00\xffgarbage\x06\x0e' + small)


def png_2x2():
    raw = b''.join(b'\x00' + bytes([255, 0, 0, 255, 0, 255, 0, 255]) for _ in range(2))
    def chunk(kind, data):
        return struct.pack('>I', len(data)) + kind + data + struct.pack('>I', zlib.crc32(kind + data) & 0xFFFFFFFF)
    return (b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', 2, 2, 8, 6, 0, 0, 0)) +
            chunk(b'IDAT', zlib.compress(raw)) + chunk(b'IEND', b''))


def gltf_seeds(out):
    os.makedirs(out, exist_ok=True)
    positions = struct.pack('<9f', 0, 0, 0, 1, 0, 0, 0, 1, 0)
    uvs = struct.pack('<6f', 0, 0, 1, 0, 0, 1)
    indices = struct.pack('<3H', 0, 1, 2) + b'\x00\x00'
    png = png_2x2()
    binary = positions + uvs + indices + png
    while len(binary) % 4:
        binary += b'\x00'
    doc = {
        'asset': {'version': '2.0'}, 'scene': 0, 'scenes': [{'nodes': [0]}],
        'nodes': [{'mesh': 0, 'rotation': [0, 0, 0, 1]}],
        'meshes': [{'primitives': [{'attributes': {'POSITION': 0, 'TEXCOORD_0': 1}, 'indices': 2, 'material': 0}]}],
        'materials': [{'pbrMetallicRoughness': {'baseColorTexture': {'index': 0}}}],
        'textures': [{'source': 0}], 'images': [{'bufferView': 3, 'mimeType': 'image/png'}],
        'buffers': [{'byteLength': len(binary)}],
        'bufferViews': [{'buffer': 0, 'byteOffset': 0, 'byteLength': 36}, {'buffer': 0, 'byteOffset': 36, 'byteLength': 24},
                        {'buffer': 0, 'byteOffset': 60, 'byteLength': 6}, {'buffer': 0, 'byteOffset': 68, 'byteLength': len(png)}],
        'accessors': [{'bufferView': 0, 'componentType': 5126, 'count': 3, 'type': 'VEC3', 'min': [0, 0, 0], 'max': [1, 1, 0]},
                      {'bufferView': 1, 'componentType': 5126, 'count': 3, 'type': 'VEC2'},
                      {'bufferView': 2, 'componentType': 5123, 'count': 3, 'type': 'SCALAR'}]}
    text = json.dumps(doc, separators=(',', ':')).encode()
    while len(text) % 4:
        text += b' '
    glb = (b'glTF' + struct.pack('<II', 2, 12 + 8 + len(text) + 8 + len(binary)) +
           struct.pack('<I', len(text)) + b'JSON' + text + struct.pack('<I', len(binary)) + b'BIN\x00' + binary)
    with open(os.path.join(out, 'triangle.glb'), 'wb') as f:
        f.write(glb)


if __name__ == '__main__':
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    klv_seeds(os.path.join(sys.argv[1], 'klv'))
    gltf_seeds(os.path.join(sys.argv[1], 'gltf'))
