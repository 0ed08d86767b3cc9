#!/usr/bin/python3
"""Decodes a PNG with only the Python standard library (zlib), independently of vdblight's
encoder, and prints "WIDTH HEIGHT MEAN_R MEAN_G MEAN_B" (means of the 8-bit values).

    /usr/bin/python3 scripts/check_png.py FILE.png [--left-right] [--raw OUT]

With --left-right it also prints the mean red minus green of the left and right thirds.
With --raw OUT it also writes the decoded pixels to OUT: rows top to bottom, the channels as
stored (3 or 4 bytes per pixel), no filter bytes: what a test compares with the encoder's input.
Exit status 1 if the file is not a valid 8-bit RGB/RGBA PNG (bad signature, CRC, size).
"""
import struct
import sys
import zlib


def decode(path):
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError("bad PNG signature")
    pos, idat, width = 8, b"", None
    while pos < len(data):
        length, kind = struct.unpack_from(">I4s", data, pos)
        body = data[pos + 8:pos + 8 + length]
        crc = struct.unpack_from(">I", data, pos + 8 + length)[0]
        if zlib.crc32(kind + body) & 0xFFFFFFFF != crc:
            raise ValueError("bad CRC in chunk %r" % kind)
        if kind == b"IHDR":
            width, height, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", body)
            if depth != 8 or colour not in (2, 6) or interlace != 0:
                raise ValueError("not 8-bit non-interlaced RGB/RGBA")
            channels = 3 if colour == 2 else 4
        elif kind == b"IDAT":
            idat += body
        elif kind == b"IEND":
            break
        pos += 12 + length
    raw = zlib.decompress(idat)
    stride = width * channels
    if len(raw) != height * (stride + 1):
        raise ValueError("image data has %d bytes, expected %d" % (len(raw), height * (stride + 1)))
    rows, prev = [], bytearray(stride)
    for r in range(height):
        f = raw[r * (stride + 1)]
        line = bytearray(raw[r * (stride + 1) + 1:(r + 1) * (stride + 1)])
        for i in range(stride):  # the five PNG filters
            a = line[i - channels] if i >= channels else 0
            b = prev[i]
            c = prev[i - channels] if i >= channels else 0
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else (b if pb <= pc else c))) & 255
            elif f != 0:
                raise ValueError("bad filter type %d" % f)
        rows.append(line)
        prev = line
    return width, height, channels, rows


def mean(rows, channels, c, x0, x1):
    vals = [row[x * channels + c] for row in rows for x in range(x0, x1)]
    return sum(vals) / max(len(vals), 1)


def main():
    try:
        w, h, ch, rows = decode(sys.argv[1])
    except (ValueError, OSError, zlib.error, struct.error) as e:
        print("invalid PNG: %s" % e)
        return 1
    print(w, h, *("%.3f" % mean(rows, ch, c, 0, w) for c in range(3)))
    if "--raw" in sys.argv:
        with open(sys.argv[sys.argv.index("--raw") + 1], "wb") as out:
            out.write(b"".join(bytes(row) for row in rows))
    if "--left-right" in sys.argv:
        third = max(w // 3, 1)
        left = mean(rows, ch, 0, 0, third) - mean(rows, ch, 1, 0, third)
        right = mean(rows, ch, 0, w - third, w) - mean(rows, ch, 1, w - third, w)
        print("left_red_minus_green %.3f right_red_minus_green %.3f" % (left, right))
    return 0


if __name__ == "__main__":
    sys.exit(main())
