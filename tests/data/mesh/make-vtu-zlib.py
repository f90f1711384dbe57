#!/usr/bin/env python3
# Write the zlib-compressed .vtu test files (tet_zlib_binary.vtu: inline base64 with UInt32
# headers; tet_zlib_appended.vtu: appended raw with UInt64 headers, blocks of 32 bytes so the
# arrays span several blocks). The layout follows VTK's vtkZLibDataCompressor: a header
# [blocks, block size, last block size, compressed sizes...], then the compressed blocks.
import base64, struct, zlib

points = [0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1]
conn = [0, 1, 2, 3, 1, 2, 3, 4]
offsets = [4, 8]
types = [10, 10]

def compressed(raw, block, header):
    blocks = [raw[i:i + block] for i in range(0, len(raw), block)] or [b""]
    packed = [zlib.compress(b) for b in blocks]
    last = len(blocks[-1]) if len(blocks[-1]) != block else 0
    fmt = "<" + header * (3 + len(packed))
    head = struct.pack(fmt, len(blocks), block, last, *[len(p) for p in packed])
    return head, b"".join(packed)

arrays = [
    ("Points", 'type="Float64" NumberOfComponents="3"', struct.pack("<15d", *points)),
    ("connectivity", 'type="Int64" Name="connectivity"', struct.pack("<8q", *conn)),
    ("offsets", 'type="Int32" Name="offsets"', struct.pack("<2i", *offsets)),
    ("types", 'type="UInt8" Name="types"', bytes(types)),
]

def document(arrays_xml, header_type, appended=b""):
    return (b'<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" version="1.0" '
            b'byte_order="LittleEndian" header_type="' + header_type.encode() +
            b'" compressor="vtkZLibDataCompressor">\n<UnstructuredGrid>\n'
            b'<Piece NumberOfPoints="5" NumberOfCells="2">\n<Points>\n' + arrays_xml[0] +
            b'</Points>\n<Cells>\n' + b"".join(arrays_xml[1:]) + b'</Cells>\n</Piece>\n'
            b'</UnstructuredGrid>\n' + appended + b'</VTKFile>\n')

xml = []
for name, attrs, raw in arrays:
    head, data = compressed(raw, 64, "I")
    text = base64.b64encode(head) + base64.b64encode(data)
    xml.append(b"<DataArray " + attrs.encode() + b' format="binary">\n' + text +
               b"\n</DataArray>\n")
open("tet_zlib_binary.vtu", "wb").write(document(xml, "UInt32"))

xml, blob = [], b""
for name, attrs, raw in arrays:
    head, data = compressed(raw, 32, "Q")
    xml.append(b"<DataArray " + attrs.encode() + b' format="appended" offset="' +
               str(len(blob)).encode() + b'"/>\n')
    blob += head + data
open("tet_zlib_appended.vtu", "wb").write(
    document(xml, "UInt64", b'<AppendedData encoding="raw">\n_' + blob + b"\n</AppendedData>\n"))
