#!/usr/bin/env python3
"""Generates the texture images that scenes/textures.lua uses (run from anywhere).

Only the standard library: zlib and struct write the PNGs. Every image is computed here, so the
repository holds no downloaded or hand-painted pixels. Values are written as linear 8-bit
(caustica reads a byte b as b / 255, with no gamma curve: docs/TEXTURES.md).

    python3 scenes/textures/make_textures.py            # writes the PNGs beside this script
"""
import math
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))


def write_png(name, width, height, pixel, gray=False):
    """Writes pixel(x, y) -> (r, g, b) floats in [0, 1] (or one float when gray) as an 8-bit PNG."""
    channels = 1 if gray else 3
    rows = bytearray()
    for y in range(height):
        rows.append(0)  # filter type: none
        for x in range(width):
            value = pixel(x, y)
            values = (value,) if gray else value
            rows.extend(max(0, min(255, round(v * 255.0))) for v in values)

    def chunk(kind, data):
        body = kind + data
        return struct.pack('>I', len(data)) + body + struct.pack('>I', zlib.crc32(body) & 0xffffffff)

    header = struct.pack('>IIBBBBB', width, height, 8, 0 if gray else 2, 0, 0, 0)
    png = (b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', header) + chunk(b'IDAT', zlib.compress(bytes(rows), 9)) +
           chunk(b'IEND', b''))
    with open(os.path.join(HERE, name), 'wb') as f:
        f.write(png)


def mix(a, b, t):
    return tuple(x + (y - x) * t for x, y in zip(a, b))


def smoothstep(e0, e1, x):
    t = max(0.0, min(1.0, (x - e0) / (e1 - e0)))
    return t * t * (3.0 - 2.0 * t)


def hash01(*ints):
    """A deterministic pseudo-random number in [0, 1) from integers."""
    h = 0x9E3779B9
    for i in ints:
        h = (h ^ (i & 0xffffffff)) * 0x85EBCA6B & 0xffffffff
        h ^= h >> 13
        h = h * 0xC2B2AE35 & 0xffffffff
        h ^= h >> 16
    return h / 2.0**32


def value_noise3(x, y, z):
    """Trilinearly interpolated lattice noise in [0, 1)."""
    xi, yi, zi = math.floor(x), math.floor(y), math.floor(z)
    fx, fy, fz = x - xi, y - yi, z - zi
    fx, fy, fz = (f * f * (3 - 2 * f) for f in (fx, fy, fz))
    total = 0.0
    for dx in (0, 1):
        for dy in (0, 1):
            for dz in (0, 1):
                w = (fx if dx else 1 - fx) * (fy if dy else 1 - fy) * (fz if dz else 1 - fz)
                total += w * hash01(xi + dx, yi + dy, zi + dz)
    return total


def fractal_noise3(x, y, z, octaves=5):
    total, amplitude, norm = 0.0, 1.0, 0.0
    for _ in range(octaves):
        total += amplitude * value_noise3(x, y, z)
        norm += amplitude
        x, y, z, amplitude = 2.03 * x, 2.03 * y, 2.03 * z, 0.5 * amplitude
    return total / norm


def die_unwrap():
    """512 x 384: a die on the cube's 4-column x 3-row cross (128-texel cells, SEED_BEHAVIOUR A2):

        row 0:           -z (5)
        row 1:  -x (4)   +y (1)   +x (3)   -y (6)
        row 2:           +z (2)

    Opposite faces sum to 7. On each side face (+-x, +-z) a dark bar runs along the edge that
    meets the top (+y) face: the cell edge that touches the +y cell in the cross, so a render
    shows the layout is the right way round when every bar hugs the die's top."""
    cell = 128
    faces = {  # (column, row): (pips, background, edge touching +y: 'left' / 'right' / 'top' / 'bottom')
        (1, 1): (1, (0.95, 0.85, 0.30), None),      # +y, top
        (0, 1): (4, (0.35, 0.75, 0.40), 'right'),   # -x: u = s_y / 4, +y at the cell's right
        (2, 1): (3, (0.35, 0.55, 0.90), 'left'),    # +x: u = (3 - s_y) / 4, +y at the left
        (3, 1): (6, (0.80, 0.40, 0.80), None),      # -y, bottom
        (1, 2): (2, (0.90, 0.45, 0.30), 'top'),     # +z, front: v = s_y / 3, +y at the top
        (1, 0): (5, (0.40, 0.80, 0.85), 'bottom'),  # -z, back: v = (3 - s_y) / 3, +y at the bottom
    }
    pip_layouts = {
        1: [(0.5, 0.5)],
        2: [(0.28, 0.28), (0.72, 0.72)],
        3: [(0.28, 0.28), (0.5, 0.5), (0.72, 0.72)],
        4: [(0.28, 0.28), (0.72, 0.28), (0.28, 0.72), (0.72, 0.72)],
        5: [(0.28, 0.28), (0.72, 0.28), (0.5, 0.5), (0.28, 0.72), (0.72, 0.72)],
        6: [(0.28, 0.25), (0.72, 0.25), (0.28, 0.5), (0.72, 0.5), (0.28, 0.75), (0.72, 0.75)],
    }
    ink = (0.08, 0.08, 0.10)

    def bar(a, b, side):
        """True on the bar along `side` of the cell; (a, b) = (across, down) in the cell, in [0, 1]."""
        along, depth = {'top': (a, b), 'bottom': (a, 1 - b), 'left': (b, a), 'right': (b, 1 - a)}[side]
        return depth < 0.09 and 0.3 < along < 0.7

    def pixel(x, y):
        key = (x // cell, y // cell)
        if key not in faces:
            return (0.5, 0.5, 0.5)
        pips, background, up_edge = faces[key]
        total = (0.0, 0.0, 0.0)
        for sx in (0.25, 0.75):  # 2 x 2 supersampling for smooth pip edges
            for sy in (0.25, 0.75):
                a, b = ((x + sx) % cell) / cell, ((y + sy) % cell) / cell  # b grows down the image
                colour = background
                if min(a, b, 1 - a, 1 - b) < 0.03:
                    colour = mix(background, ink, 0.6)  # border
                if up_edge and bar(a, b, up_edge):
                    colour = ink
                for px, py in pip_layouts[pips]:
                    if (a - px) ** 2 + (b - py) ** 2 < 0.085 ** 2:
                        colour = ink
                total = tuple(t + 0.25 * c for t, c in zip(total, colour))
        return total

    write_png('die_unwrap.png', 4 * cell, 3 * cell, pixel)


def globe():
    """512 x 256 map of an imaginary planet for the sphere's uv (SEED_BEHAVIOUR A2):
    u = 1/2 + atan2(-z, x) / 2 pi, v = (1 + y) / 2, so the centre column is +x, the seam -x, the
    top row the north pole, and rows are linear in height (an equal-area map). Each texel is
    drawn from the point of the sphere it lands on, so the map has no seam: noise continents on
    an ocean, ice caps, and a graticule every 30 degrees of longitude and latitude."""
    width, height = 512, 256
    ocean_deep, ocean_shallow = (0.05, 0.15, 0.45), (0.15, 0.45, 0.75)
    lowland, highland, ice = (0.25, 0.60, 0.20), (0.55, 0.45, 0.25), (0.95, 0.97, 1.0)
    parallels = [(1 + math.sin(math.radians(lat))) / 2 for lat in (-60, -30, 0, 30, 60)]

    def pixel(x, y):
        u, v = (x + 0.5) / width, 1 - (y + 0.5) / height  # row 0 is v = 1
        phi, height_y = 2 * math.pi * (u - 0.5), 2 * v - 1
        ring = math.sqrt(max(0.0, 1 - height_y * height_y))
        p = (ring * math.cos(phi), height_y, -ring * math.sin(phi))  # atan2(-z, x) = phi
        n = fractal_noise3(2.2 * p[0] + 5.0, 2.2 * p[1] + 5.0, 2.2 * p[2] + 5.0)
        if n < 0.52:
            colour = mix(ocean_deep, ocean_shallow, smoothstep(0.35, 0.52, n))
        else:
            colour = mix(lowland, highland, smoothstep(0.55, 0.7, n))
        latitude = math.degrees(math.asin(height_y))
        if abs(latitude) > 64.0 + 8.0 * n:
            colour = ice
        columns_to_meridian = abs((u * 12 + 0.5) % 1 - 0.5) * width / 12  # meridians every 30 degrees
        rows_to_parallel = min(abs(v - vp) for vp in parallels) * height
        if min(columns_to_meridian, rows_to_parallel) < 0.75:
            colour = mix(colour, (1.0, 1.0, 1.0), 0.5)
        return colour

    write_png('globe.png', width, height, pixel)


def compass():
    """256 x 256 compass rose for a cylinder's top cap through cyltop (SEED_BEHAVIOUR A3): the
    cap maps to the whole image with u' = (1 + x) / 2 and v' = (1 + z) / 2, so the image's right
    is +x and its BOTTOM row is -z. Seen from above with -z away from the viewer the image shows
    upside down, so it is drawn flipped: the red north point at the image's bottom (the cap's
    -z side), east at the right. Rings and an eight-point star."""
    size = 256

    def pixel(x, y):
        total = (0.0, 0.0, 0.0)
        for sx in (0.25, 0.75):
            for sy in (0.25, 0.75):
                # (east, north) as seen from above: east = +x = image right, north = -z = image down.
                east, north = 2 * (x + sx) / size - 1, 2 * (y + sy) / size - 1
                r, angle = math.hypot(east, north), math.atan2(east, north)  # angle 0 = north, clockwise
                colour = (0.93, 0.88, 0.75)
                if 0.88 < r < 0.93 or 0.60 < r < 0.62:
                    colour = (0.25, 0.2, 0.15)
                # Star: points every 45 degrees, long ones at the cardinal directions.
                sector = (angle + math.pi / 8) % (math.pi / 4) - math.pi / 8
                point_length = 0.85 if round(angle / (math.pi / 4)) % 2 == 0 else 0.5
                if r < point_length * (1 - abs(sector) / (math.pi / 8)) ** 1.5 + 0.05:
                    cardinal = round(angle / (math.pi / 4)) % 8
                    colour = (0.8, 0.1, 0.1) if cardinal == 0 else (0.15, 0.2, 0.45)
                    if sector < 0:
                        colour = mix(colour, (1.0, 1.0, 1.0), 0.35)
                total = tuple(t + 0.25 * c for t, c in zip(total, colour))
        return total

    write_png('compass.png', size, size, pixel)


def hsv(h, s, v):
    i = int(h * 6) % 6
    f = h * 6 - math.floor(h * 6)
    p, q, t = v * (1 - s), v * (1 - f * s), v * (1 - (1 - f) * s)
    return [(v, t, p), (q, v, p), (p, v, t), (p, q, v), (t, p, v), (v, p, q)][i]


def colour_wheel():
    """256 x 256 colour wheel with a spiral for a cone's flat base through conetop
    (SEED_BEHAVIOUR A3): the base disc maps to the circle inscribed in the image, u' = (1 + x) / 2,
    v' = (1 + z) / 2, its centre at the image's centre. Hue by angle around the centre, bands
    along a spiral, white at the centre, a dark rim at the disc's edge."""
    size = 256

    def pixel(x, y):
        px, py = 2 * (x + 0.5) / size - 1, 2 * (y + 0.5) / size - 1
        r, angle = math.hypot(px, py), math.atan2(py, px)
        hue = (angle / (2 * math.pi)) % 1.0
        band = 0.5 + 0.5 * math.cos(2 * math.pi * (6 * r - 2 * angle / (2 * math.pi)))
        value = 0.55 + 0.45 * smoothstep(0.2, 0.8, band)
        if 0.94 < r:
            return (0.12, 0.1, 0.1)  # the rim of the disc (and the unused corners)
        return hsv(hue, min(1.0, 4 * r), value)

    write_png('colour_wheel.png', size, size, pixel)


def bricks(bump):
    """256 x 256 running-bond bricks: 8 courses of 32 texels, 4 bricks of 64 texels per course.
    Colour: per-brick tint and speckle. Bump (gray): brick faces at 0.8-1, mortar at 0, edges
    rounded over 6 texels."""
    size, course, brick, mortar = 256, 32, 64, 3

    def pixel(x, y):
        row = y // course
        shifted = x + (brick // 2 if row % 2 else 0)
        column = (shifted // brick) % (size // brick)
        bx, by = shifted % brick, y % course
        edge = min(bx, brick - 1 - bx, by, course - 1 - by) - mortar + 0.5  # texels inside the brick face
        face = smoothstep(0.0, 6.0, edge)
        grain = hash01(x, y, 7)
        if bump:
            return face * (0.85 + 0.15 * hash01(row, column, 3)) - 0.04 * grain * face
        tint = hash01(row, column, 11)
        brick_colour = mix((0.55, 0.20, 0.12), (0.75, 0.38, 0.22), tint)
        brick_colour = mix(brick_colour, (0.3, 0.12, 0.08), 0.25 * grain)
        mortar_colour = (0.72, 0.70, 0.66)
        return mix(mortar_colour, brick_colour, smoothstep(0.0, 1.0, edge))

    write_png('bricks_bump.png' if bump else 'bricks.png', size, size, pixel, gray=bump)


if __name__ == '__main__':
    die_unwrap()
    globe()
    compass()
    colour_wheel()
    bricks(bump=False)
    bricks(bump=True)
