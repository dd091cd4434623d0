"""Checksum families of CAN messages: the reference the C decoder
(lib/can/can_checksum.c) is tested against, integers only.

Each family is named as opendbc names the scheme (opendbc/can/dbc.py: the
SignalType of the CHECKSUM signal; the classic Hyundai schemes are those of
opendbc's Hyundai safety code). The checksum sits in a field of the message
(FIELDS says where it may be); `compute(family, frame_id, extended, data,
field, magic)` gives the value that field must hold.

  toyota          sum of the id's bytes, the length and every payload byte
                  but the checksum byte, mod 256
  honda           4 bits in the low nibble of the last byte: 8 - (sum of the
                  id's nibbles and every payload nibble but the checksum's),
                  + 3 for a 29-bit id, mod 16
  hkg_can_fd      Hyundai/Kia CAN FD: CRC-16 (poly 0x1021, init 0) over bytes
                  2.., then the id's low and high byte, XOR a constant of the
                  length (8: 0x5F29, 16: 0x041D, 24: 0x819D, 32: 0x9F5B);
                  bytes 0-1, little-endian
  hyundai         classic Hyundai/Kia CAN: a 4-bit field, (16 - sum of every
                  payload nibble but the checksum's) mod 16
  hyundai_whl_spd classic Hyundai/Kia WHL_SPD11: number of 1 bits outside bits
                  6-7 of bytes 1, 3, 5, 7, XOR 9, mod 16; the checksum's low
                  two bits in bits 6-7 of byte 5, its high two in byte 7
  volkswagen_mqb  AUTOSAR E2E profile 2: CRC-8 (poly 0x2F, init 0xFF) over
                  bytes 1.., then the message's magic byte for the counter
                  (low nibble of byte 1), XOR 0xFF; byte 0
  subaru          sum of the id's bytes and bytes 1.., mod 256; byte 0
  chrysler        CRC-8 (poly 0x1D, init 0xFF, XOR 0xFF) over all bytes but
                  the last; last byte
  fca_giorgio     CRC-8 (poly 0x1D, init 0) over all bytes but the last, XOR
                  the message's constant; last byte
  nissan          CRC-8 (poly 0x1D, init 0, XOR 0xFF) over all bytes but the
                  last; last byte
  ford            0xFF - sum of the protected bytes and fields (two messages:
                  BrakeSysFeatures 0x415, Yaw_Data_FD1 0x91)
  xor             XOR of every payload byte but the checksum byte (VW PQ)
"""

FAMILIES = ["none", "toyota", "honda", "hkg_can_fd", "hyundai", "hyundai_whl_spd", "volkswagen_mqb",
            "subaru", "chrysler", "fca_giorgio", "nissan", "ford", "xor"]
FAMILY_INDEX = {f: i for i, f in enumerate(FAMILIES)}
ALIASES = {"vw_mqb": "volkswagen_mqb", "volkswagen_mqb_meb": "volkswagen_mqb", "hyundai_canfd": "hkg_can_fd",
           "hkg_canfd": "hkg_can_fd", "vw_pq": "xor"}
MAGIC_LEN = 16

# FCA Giorgio: the final XOR of each message (opendbc: the EPS messages have their own).
FCA_GIORGIO_XOR = {0xDE: 0x10, 0x106: 0xF6, 0x122: 0xF1}
FCA_GIORGIO_XOR_DEFAULT = 0x0A
# Ford: the payload byte holding the checksum of each message the family covers.
FORD_CHECKSUM_BYTE = {0x415: 3, 0x91: 4}

# VW MQB: per message, the magic byte for each counter value (AUTOSAR E2E
# "data id" list), as opendbc lists them.
VW_MQB_MAGIC = {
    0x40: [0x40] * 16, 0x86: [0x86] * 16, 0x9F: [0xF5] * 16,
    0xAD: [0x3F, 0x69, 0x39, 0xDC, 0x94, 0xF9, 0x14, 0x64, 0xD8, 0x6A, 0x34, 0xCE, 0xA2, 0x55, 0xB5, 0x2C],
    0xDB: [0x09, 0xFA, 0xCA, 0x8E, 0x62, 0xD5, 0xD1, 0xF0, 0x31, 0xA0, 0xAF, 0xDA, 0x4D, 0x1A, 0x0A, 0x97],
    0xFC: [0x77, 0x5C, 0xA0, 0x89, 0x4B, 0x7C, 0xBB, 0xD6, 0x1F, 0x6C, 0x4F, 0xF6, 0x20, 0x2B, 0x43, 0xDD],
    0xFD: [0xB4, 0xEF, 0xF8, 0x49, 0x1E, 0xE5, 0xC2, 0xC0, 0x97, 0x19, 0x3C, 0xC9, 0xF1, 0x98, 0xD6, 0x61],
    0x101: [0xAA] * 16,
    0x102: [0xD7, 0x12, 0x85, 0x7E, 0x0B, 0x34, 0xFA, 0x16, 0x7A, 0x25, 0x2D, 0x8F, 0x04, 0x8E, 0x5D, 0x35],
    0x106: [0x07] * 16,
    0x10B: [0x77, 0x5C, 0xA0, 0x89, 0x4B, 0x7C, 0xBB, 0xD6, 0x1F, 0x6C, 0x4F, 0xF6, 0x20, 0x2B, 0x43, 0xDD],
    0x116: [0xAC] * 16, 0x117: [0x16] * 16,
    0x120: [0xC4, 0xE2, 0x4F, 0xE4, 0xF8, 0x2F, 0x56, 0x81, 0x9F, 0xE5, 0x83, 0x44, 0x05, 0x3F, 0x97, 0xDF],
    0x121: [0xE9, 0x65, 0xAE, 0x6B, 0x7B, 0x35, 0xE5, 0x5F, 0x4E, 0xC7, 0x86, 0xA2, 0xBB, 0xDD, 0xEB, 0xB4],
    0x122: [0x37, 0x7D, 0xF3, 0xA9, 0x18, 0x46, 0x6D, 0x4D, 0x3D, 0x71, 0x92, 0x9C, 0xE5, 0x32, 0x10, 0xB9],
    0x126: [0xDA] * 16,
    0x12B: [0x6A, 0x38, 0xB4, 0x27, 0x22, 0xEF, 0xE1, 0xBB, 0xF8, 0x80, 0x84, 0x49, 0xC7, 0x9E, 0x1E, 0x2B],
    0x12E: [0xF8, 0xE5, 0x97, 0xC9, 0xD6, 0x07, 0x47, 0x21, 0x66, 0xDD, 0xCF, 0x6F, 0xA1, 0x94, 0x74, 0x63],
    0x139: [0xED, 0x03, 0x1C, 0x13, 0xC6, 0x23, 0x78, 0x7A, 0x8B, 0x40, 0x14, 0x51, 0xBF, 0x68, 0x32, 0xBA],
    0x13D: [0x20, 0xCA, 0x68, 0xD5, 0x1B, 0x31, 0xE2, 0xDA, 0x08, 0x0A, 0xD4, 0xDE, 0x9C, 0xE4, 0x35, 0x5B],
    0x14C: [0x16, 0x35, 0x59, 0x15, 0x9A, 0x2A, 0x97, 0xB8, 0x0E, 0x4E, 0x30, 0xCC, 0xB3, 0x07, 0x01, 0xAD],
    0x14D: [0x1A, 0x65, 0x81, 0x96, 0xC0, 0xDF, 0x11, 0x92, 0xD3, 0x61, 0xC6, 0x95, 0x8C, 0x29, 0x21, 0xB5],
    0x187: [0x7F, 0xED, 0x17, 0xC2, 0x7C, 0xEB, 0x44, 0x21, 0x01, 0xFA, 0xDB, 0x15, 0x4A, 0x6B, 0x23, 0x05],
    0x1A4: [0x69, 0xBB, 0x54, 0xE6, 0x4E, 0x46, 0x8D, 0x7B, 0xEA, 0x87, 0xE9, 0xB3, 0x63, 0xCE, 0xF8, 0xBF],
    0x1AB: [0x13, 0x21, 0x9B, 0x6A, 0x9A, 0x62, 0xD4, 0x65, 0x18, 0xF1, 0xAB, 0x16, 0x32, 0x89, 0xE7, 0x26],
    0x1F0: [0x2F, 0x3C, 0x22, 0x60, 0x18, 0xEB, 0x63, 0x76, 0xC5, 0x91, 0x0F, 0x27, 0x34, 0x04, 0x7F, 0x02],
    0x20A: [0x9D, 0xE8, 0x36, 0xA1, 0xCA, 0x3B, 0x1D, 0x33, 0xE0, 0xD5, 0xBB, 0x5F, 0xAE, 0x3C, 0x31, 0x9F],
    0x25D: [0xDA, 0x6B, 0x0E, 0xB2, 0x78, 0xBD, 0x5A, 0x81, 0x7B, 0xD6, 0x41, 0x39, 0x76, 0xB6, 0xD7, 0x35],
    0x26B: [0xCE, 0xCC, 0xBD, 0x69, 0xA1, 0x3C, 0x18, 0x76, 0x0F, 0x04, 0xF2, 0x3A, 0x93, 0x24, 0x19, 0x51],
    0x30C: [0x0F] * 16, 0x30F: [0x0C] * 16, 0x324: [0x27] * 16,
    0x3BE: [0x1F, 0x28, 0xC6, 0x85, 0xE6, 0xF8, 0xB0, 0x19, 0x5B, 0x64, 0x35, 0x21, 0xE4, 0xF7, 0x9C, 0x24],
    0x3C0: [0xC3] * 16,
    0x3D5: [0xC5, 0x39, 0xC7, 0xF9, 0x92, 0xD8, 0x24, 0xCE, 0xF1, 0xB5, 0x7A, 0xC4, 0xBC, 0x60, 0xE3, 0xD1],
    0x65D: [0xAC, 0xB3, 0xAB, 0xEB, 0x7A, 0xE1, 0x3B, 0xF7, 0x73, 0xBA, 0x7C, 0x9E, 0x06, 0x5F, 0x02, 0xD9],
}

HKG_CAN_FD_XOR = {8: 0x5F29, 16: 0x041D, 24: 0x819D, 32: 0x9F5B}


def crc8_table(poly):
    table = []
    for i in range(256):
        c = i
        for _ in range(8):
            c = ((c << 1) ^ poly) & 0xFF if c & 0x80 else (c << 1) & 0xFF
        table.append(c)
    return table


def crc16_table(poly):
    table = []
    for i in range(256):
        c = i << 8
        for _ in range(8):
            c = ((c << 1) ^ poly) & 0xFFFF if c & 0x8000 else (c << 1) & 0xFFFF
        table.append(c)
    return table


CRC8_2F = crc8_table(0x2F)
CRC8_1D = crc8_table(0x1D)
CRC16_1021 = crc16_table(0x1021)


def crc8(table, init, data):
    c = init
    for b in data:
        c = table[c ^ b]
    return c


def crc16(table, init, data):
    c = init
    for b in data:
        c = ((c << 8) & 0xFFFF) ^ table[(c >> 8) ^ b]
    return c


def _nibbles(b):
    return (b & 0xF) + (b >> 4)


def field_bits(start, length, order):
    """The payload bit positions (8 * byte + bit) of a DBC field."""
    if order == "intel":
        return [start + i for i in range(length)]
    bits = []
    pos = start
    for _ in range(length):
        bits.append(pos)
        pos = pos - 1 if pos % 8 else pos + 15
    return bits


class Field:
    """Where a checksum sits: DBC start bit, length, byte order."""

    def __init__(self, start, length, order):
        self.start, self.length, self.order = start, length, order

    @property
    def bits(self):
        return set(field_bits(self.start, self.length, self.order))

    @property
    def byte(self):
        return min(self.bits) // 8


def _byte_field(data_len, byte):
    return Field(8 * byte, 8, "intel")


def expected_field(family, frame_id, length):
    """Field(s) the family needs: (description, predicate(Field) -> bool)."""
    last = length - 1

    def whole_byte(f, byte=None):
        bits = f.bits
        b = min(bits) // 8
        return len(bits) == 8 and bits == set(range(8 * b, 8 * b + 8)) and (byte is None or b == byte)
    if family in ("toyota", "xor"):
        return "one whole byte", lambda f: whole_byte(f)
    if family == "honda":
        return "the low nibble of the last byte", lambda f: f.bits == set(range(8 * last, 8 * last + 4))
    if family == "hkg_can_fd":
        return "bytes 0-1 (16 bits, Intel)", lambda f: f.length == 16 and f.start == 0 and f.order == "intel"
    if family == "hyundai":
        return "one whole nibble", lambda f: f.length == 4 and min(f.bits) % 4 == 0 and \
            f.bits == set(range(min(f.bits), min(f.bits) + 4))
    if family == "hyundai_whl_spd":
        return "bits 6-7 of byte 5 (WHL_SPD11's Checksum_LSB, 46|2 Intel) in an 8-byte message", \
            lambda f: length == 8 and f.bits == {46, 47}
    if family in ("volkswagen_mqb", "subaru"):
        return "byte 0", lambda f: whole_byte(f, 0)
    if family in ("chrysler", "fca_giorgio", "nissan"):
        return "the last byte", lambda f: whole_byte(f, last)
    if family == "ford":
        b = FORD_CHECKSUM_BYTE.get(frame_id)
        if b is None:
            return "a message Ford's checksum is known for (0x415 BrakeSysFeatures, 0x91 Yaw_Data_FD1)", \
                lambda f: False
        return f"byte {b}", lambda f: whole_byte(f, b) and length == 8
    return "", lambda f: True


def compute(family, frame_id, extended, data, field, magic=None):
    """The value the checksum field of this frame must hold."""
    data = bytes(data)
    n = len(data)
    if family == "toyota":
        s = n + sum((frame_id >> sh) & 0xFF for sh in (0, 8, 16, 24))
        s += sum(b for i, b in enumerate(data) if i != field.byte)
        return s & 0xFF
    if family == "honda":
        s = 0
        a = frame_id
        while a:
            s += a & 0xF
            a >>= 4
        for i, b in enumerate(data):
            s += (b >> 4) if i == n - 1 else _nibbles(b)
        s = 8 - s + (3 if extended else 0)
        return s & 0xF
    if family == "hkg_can_fd":
        c = crc16(CRC16_1021, 0, data[2:] + bytes([frame_id & 0xFF, (frame_id >> 8) & 0xFF]))
        return c ^ HKG_CAN_FD_XOR.get(n, 0)
    if family == "hyundai":
        cs = field.bits
        s = 0
        for i, b in enumerate(data):
            for half in (0, 4):
                if 8 * i + half not in cs:
                    s += (b >> half) & 0xF
        return (16 - s % 16) % 16
    if family == "hyundai_whl_spd":
        count = 0
        for i, b in enumerate(data):
            mask = 0x3F if i in (1, 3, 5, 7) else 0xFF
            count += bin(b & mask).count("1")
        return (count ^ 9) & 0xF
    if family == "volkswagen_mqb":
        c = crc8(CRC8_2F, 0xFF, data[1:])
        c = CRC8_2F[c ^ magic[data[1] & 0x0F]]
        return c ^ 0xFF
    if family == "subaru":
        s = sum((frame_id >> sh) & 0xFF for sh in (0, 8, 16, 24)) + sum(data[1:])
        return s & 0xFF
    if family == "chrysler":
        return crc8(CRC8_1D, 0xFF, data[:-1]) ^ 0xFF
    if family == "fca_giorgio":
        return crc8(CRC8_1D, 0x00, data[:-1]) ^ magic[0]
    if family == "nissan":
        return crc8(CRC8_1D, 0x00, data[:-1]) ^ 0xFF
    if family == "ford":
        if frame_id == 0x415:
            s = data[0] + data[1] + (data[2] >> 6) + ((data[2] >> 2) & 0xF)
        else:
            s = data[0] + data[1] + data[2] + data[3] + data[5] + (data[6] >> 6) + ((data[6] >> 4) & 0x3)
        return (0xFF - s) & 0xFF
    if family == "xor":
        x = 0
        for i, b in enumerate(data):
            if i != field.byte:
                x ^= b
        return x
    raise ValueError(f"checksum family {family!r} unknown")


def received(family, data, field):
    """The checksum the frame carries."""
    from grip_tools.can.dbc import extract
    if family == "hyundai_whl_spd":
        return ((data[7] >> 6) << 2) | (data[5] >> 6)
    return extract(bytes(data), field.start, field.length, field.order, 0)


def default_magic(family, frame_id):
    """The family's constants for this message, or None if it needs some and none are known."""
    if family == "volkswagen_mqb":
        m = VW_MQB_MAGIC.get(frame_id)
        return list(m) if m else None
    if family == "fca_giorgio":
        return [FCA_GIORGIO_XOR.get(frame_id, FCA_GIORGIO_XOR_DEFAULT)] + [0] * 15
    return [0] * MAGIC_LEN


# DBC file name -> family of its CHECKSUM signals (opendbc/can/dbc.py's
# get_checksum_state), and the families whose checksums opendbc's safety code
# checks on a few messages only (BY_ID: their checksum and counter signals).
PREFIXES = [
    (("honda_", "acura_"), "honda"), (("toyota_", "lexus_"), "toyota"),
    (("hyundai_canfd",), "hkg_can_fd"), (("vw_mqb", "vw_mqbevo", "vw_meb"), "volkswagen_mqb"),
    (("vw_pq",), "xor"), (("subaru_global_",), "subaru"), (("chrysler_",), "chrysler"),
    (("fca_giorgio",), "fca_giorgio"), (("ford_",), "ford"),
    (("hyundai_can", "hyundai_kia_generic", "hyundai_palisade", "hyundai_2015_ccan"), "hyundai"),
]
BY_ID = {
    "hyundai": {0x386: ("hyundai_whl_spd", "WHL_SPD_Checksum_LSB", "WHL_SPD_AliveCounter_LSB"),
                0x260: ("hyundai", "Checksum", "AliveCounter"),
                0x421: ("hyundai", "CR_VSM_ChkSum", None)},
    "ford": {0x415: ("ford", "VehVActlBrk_No_Cs", "VehVActlBrk_No_Cnt"),
             0x91: ("ford", "VehRollYawW_No_Cs", "VehRollYaw_No_Cnt")},
}


def auto_check(dbc_family, frame_id, signal_names):
    """(family, checksum signal, counter signal or None) a message of a DBC
    of this family gets without a word in the map, or None."""
    if dbc_family is None:
        return None
    if dbc_family in BY_ID:
        hit = BY_ID[dbc_family].get(frame_id)
        if hit and hit[1] in signal_names:
            return hit[0], hit[1], hit[2] if hit[2] in signal_names else None
        return None
    if "CHECKSUM" in signal_names:
        return dbc_family, "CHECKSUM", "COUNTER" if "COUNTER" in signal_names else None
    return None


def family_of_dbc(path):
    """The checksum family opendbc gives a DBC by its file name, or None."""
    import os
    stem = os.path.basename(path)
    stem = stem[:-4] if stem.lower().endswith(".dbc") else stem
    stem = stem.lstrip("_")
    for prefixes, fam in PREFIXES:
        if stem.startswith(prefixes):
            return fam
    return None
