/*
 * can_checksum.c - checksum families of CAN messages (grip_can.h,
 * docs/can-families.md): the value a frame's checksum field must hold, and
 * which fields each family can use. Integer arithmetic only; every loop is
 * bounded by the payload (<= 64 bytes); the CRCs are table-driven.
 * Reference: tools/grip_tools/can/checksums.py (tests compare both on real
 * frames and every single-bit error of them).
 */
#include <stddef.h>

#include "grip/grip_can.h"
#include "can_internal.h"

/* CRC-8, polynomial 0x2F (AUTOSAR, Volkswagen MQB), MSB first: T[i] = i * x^8 mod P. */
static const uint8_t CRC8_2F[256] = {
    0x00u, 0x2Fu, 0x5Eu, 0x71u, 0xBCu, 0x93u, 0xE2u, 0xCDu, 0x57u, 0x78u, 0x09u, 0x26u,
    0xEBu, 0xC4u, 0xB5u, 0x9Au, 0xAEu, 0x81u, 0xF0u, 0xDFu, 0x12u, 0x3Du, 0x4Cu, 0x63u,
    0xF9u, 0xD6u, 0xA7u, 0x88u, 0x45u, 0x6Au, 0x1Bu, 0x34u, 0x73u, 0x5Cu, 0x2Du, 0x02u,
    0xCFu, 0xE0u, 0x91u, 0xBEu, 0x24u, 0x0Bu, 0x7Au, 0x55u, 0x98u, 0xB7u, 0xC6u, 0xE9u,
    0xDDu, 0xF2u, 0x83u, 0xACu, 0x61u, 0x4Eu, 0x3Fu, 0x10u, 0x8Au, 0xA5u, 0xD4u, 0xFBu,
    0x36u, 0x19u, 0x68u, 0x47u, 0xE6u, 0xC9u, 0xB8u, 0x97u, 0x5Au, 0x75u, 0x04u, 0x2Bu,
    0xB1u, 0x9Eu, 0xEFu, 0xC0u, 0x0Du, 0x22u, 0x53u, 0x7Cu, 0x48u, 0x67u, 0x16u, 0x39u,
    0xF4u, 0xDBu, 0xAAu, 0x85u, 0x1Fu, 0x30u, 0x41u, 0x6Eu, 0xA3u, 0x8Cu, 0xFDu, 0xD2u,
    0x95u, 0xBAu, 0xCBu, 0xE4u, 0x29u, 0x06u, 0x77u, 0x58u, 0xC2u, 0xEDu, 0x9Cu, 0xB3u,
    0x7Eu, 0x51u, 0x20u, 0x0Fu, 0x3Bu, 0x14u, 0x65u, 0x4Au, 0x87u, 0xA8u, 0xD9u, 0xF6u,
    0x6Cu, 0x43u, 0x32u, 0x1Du, 0xD0u, 0xFFu, 0x8Eu, 0xA1u, 0xE3u, 0xCCu, 0xBDu, 0x92u,
    0x5Fu, 0x70u, 0x01u, 0x2Eu, 0xB4u, 0x9Bu, 0xEAu, 0xC5u, 0x08u, 0x27u, 0x56u, 0x79u,
    0x4Du, 0x62u, 0x13u, 0x3Cu, 0xF1u, 0xDEu, 0xAFu, 0x80u, 0x1Au, 0x35u, 0x44u, 0x6Bu,
    0xA6u, 0x89u, 0xF8u, 0xD7u, 0x90u, 0xBFu, 0xCEu, 0xE1u, 0x2Cu, 0x03u, 0x72u, 0x5Du,
    0xC7u, 0xE8u, 0x99u, 0xB6u, 0x7Bu, 0x54u, 0x25u, 0x0Au, 0x3Eu, 0x11u, 0x60u, 0x4Fu,
    0x82u, 0xADu, 0xDCu, 0xF3u, 0x69u, 0x46u, 0x37u, 0x18u, 0xD5u, 0xFAu, 0x8Bu, 0xA4u,
    0x05u, 0x2Au, 0x5Bu, 0x74u, 0xB9u, 0x96u, 0xE7u, 0xC8u, 0x52u, 0x7Du, 0x0Cu, 0x23u,
    0xEEu, 0xC1u, 0xB0u, 0x9Fu, 0xABu, 0x84u, 0xF5u, 0xDAu, 0x17u, 0x38u, 0x49u, 0x66u,
    0xFCu, 0xD3u, 0xA2u, 0x8Du, 0x40u, 0x6Fu, 0x1Eu, 0x31u, 0x76u, 0x59u, 0x28u, 0x07u,
    0xCAu, 0xE5u, 0x94u, 0xBBu, 0x21u, 0x0Eu, 0x7Fu, 0x50u, 0x9Du, 0xB2u, 0xC3u, 0xECu,
    0xD8u, 0xF7u, 0x86u, 0xA9u, 0x64u, 0x4Bu, 0x3Au, 0x15u, 0x8Fu, 0xA0u, 0xD1u, 0xFEu,
    0x33u, 0x1Cu, 0x6Du, 0x42u
};

/* CRC-8, polynomial 0x1D (SAE J1850: Chrysler, FCA Giorgio, Nissan), MSB first. */
static const uint8_t CRC8_1D[256] = {
    0x00u, 0x1Du, 0x3Au, 0x27u, 0x74u, 0x69u, 0x4Eu, 0x53u, 0xE8u, 0xF5u, 0xD2u, 0xCFu,
    0x9Cu, 0x81u, 0xA6u, 0xBBu, 0xCDu, 0xD0u, 0xF7u, 0xEAu, 0xB9u, 0xA4u, 0x83u, 0x9Eu,
    0x25u, 0x38u, 0x1Fu, 0x02u, 0x51u, 0x4Cu, 0x6Bu, 0x76u, 0x87u, 0x9Au, 0xBDu, 0xA0u,
    0xF3u, 0xEEu, 0xC9u, 0xD4u, 0x6Fu, 0x72u, 0x55u, 0x48u, 0x1Bu, 0x06u, 0x21u, 0x3Cu,
    0x4Au, 0x57u, 0x70u, 0x6Du, 0x3Eu, 0x23u, 0x04u, 0x19u, 0xA2u, 0xBFu, 0x98u, 0x85u,
    0xD6u, 0xCBu, 0xECu, 0xF1u, 0x13u, 0x0Eu, 0x29u, 0x34u, 0x67u, 0x7Au, 0x5Du, 0x40u,
    0xFBu, 0xE6u, 0xC1u, 0xDCu, 0x8Fu, 0x92u, 0xB5u, 0xA8u, 0xDEu, 0xC3u, 0xE4u, 0xF9u,
    0xAAu, 0xB7u, 0x90u, 0x8Du, 0x36u, 0x2Bu, 0x0Cu, 0x11u, 0x42u, 0x5Fu, 0x78u, 0x65u,
    0x94u, 0x89u, 0xAEu, 0xB3u, 0xE0u, 0xFDu, 0xDAu, 0xC7u, 0x7Cu, 0x61u, 0x46u, 0x5Bu,
    0x08u, 0x15u, 0x32u, 0x2Fu, 0x59u, 0x44u, 0x63u, 0x7Eu, 0x2Du, 0x30u, 0x17u, 0x0Au,
    0xB1u, 0xACu, 0x8Bu, 0x96u, 0xC5u, 0xD8u, 0xFFu, 0xE2u, 0x26u, 0x3Bu, 0x1Cu, 0x01u,
    0x52u, 0x4Fu, 0x68u, 0x75u, 0xCEu, 0xD3u, 0xF4u, 0xE9u, 0xBAu, 0xA7u, 0x80u, 0x9Du,
    0xEBu, 0xF6u, 0xD1u, 0xCCu, 0x9Fu, 0x82u, 0xA5u, 0xB8u, 0x03u, 0x1Eu, 0x39u, 0x24u,
    0x77u, 0x6Au, 0x4Du, 0x50u, 0xA1u, 0xBCu, 0x9Bu, 0x86u, 0xD5u, 0xC8u, 0xEFu, 0xF2u,
    0x49u, 0x54u, 0x73u, 0x6Eu, 0x3Du, 0x20u, 0x07u, 0x1Au, 0x6Cu, 0x71u, 0x56u, 0x4Bu,
    0x18u, 0x05u, 0x22u, 0x3Fu, 0x84u, 0x99u, 0xBEu, 0xA3u, 0xF0u, 0xEDu, 0xCAu, 0xD7u,
    0x35u, 0x28u, 0x0Fu, 0x12u, 0x41u, 0x5Cu, 0x7Bu, 0x66u, 0xDDu, 0xC0u, 0xE7u, 0xFAu,
    0xA9u, 0xB4u, 0x93u, 0x8Eu, 0xF8u, 0xE5u, 0xC2u, 0xDFu, 0x8Cu, 0x91u, 0xB6u, 0xABu,
    0x10u, 0x0Du, 0x2Au, 0x37u, 0x64u, 0x79u, 0x5Eu, 0x43u, 0xB2u, 0xAFu, 0x88u, 0x95u,
    0xC6u, 0xDBu, 0xFCu, 0xE1u, 0x5Au, 0x47u, 0x60u, 0x7Du, 0x2Eu, 0x33u, 0x14u, 0x09u,
    0x7Fu, 0x62u, 0x45u, 0x58u, 0x0Bu, 0x16u, 0x31u, 0x2Cu, 0x97u, 0x8Au, 0xADu, 0xB0u,
    0xE3u, 0xFEu, 0xD9u, 0xC4u
};

/* CRC-16, polynomial 0x1021 (Hyundai/Kia CAN FD), MSB first. */
static const uint16_t CRC16_1021[256] = {
    0x0000u, 0x1021u, 0x2042u, 0x3063u, 0x4084u, 0x50A5u, 0x60C6u, 0x70E7u,
    0x8108u, 0x9129u, 0xA14Au, 0xB16Bu, 0xC18Cu, 0xD1ADu, 0xE1CEu, 0xF1EFu,
    0x1231u, 0x0210u, 0x3273u, 0x2252u, 0x52B5u, 0x4294u, 0x72F7u, 0x62D6u,
    0x9339u, 0x8318u, 0xB37Bu, 0xA35Au, 0xD3BDu, 0xC39Cu, 0xF3FFu, 0xE3DEu,
    0x2462u, 0x3443u, 0x0420u, 0x1401u, 0x64E6u, 0x74C7u, 0x44A4u, 0x5485u,
    0xA56Au, 0xB54Bu, 0x8528u, 0x9509u, 0xE5EEu, 0xF5CFu, 0xC5ACu, 0xD58Du,
    0x3653u, 0x2672u, 0x1611u, 0x0630u, 0x76D7u, 0x66F6u, 0x5695u, 0x46B4u,
    0xB75Bu, 0xA77Au, 0x9719u, 0x8738u, 0xF7DFu, 0xE7FEu, 0xD79Du, 0xC7BCu,
    0x48C4u, 0x58E5u, 0x6886u, 0x78A7u, 0x0840u, 0x1861u, 0x2802u, 0x3823u,
    0xC9CCu, 0xD9EDu, 0xE98Eu, 0xF9AFu, 0x8948u, 0x9969u, 0xA90Au, 0xB92Bu,
    0x5AF5u, 0x4AD4u, 0x7AB7u, 0x6A96u, 0x1A71u, 0x0A50u, 0x3A33u, 0x2A12u,
    0xDBFDu, 0xCBDCu, 0xFBBFu, 0xEB9Eu, 0x9B79u, 0x8B58u, 0xBB3Bu, 0xAB1Au,
    0x6CA6u, 0x7C87u, 0x4CE4u, 0x5CC5u, 0x2C22u, 0x3C03u, 0x0C60u, 0x1C41u,
    0xEDAEu, 0xFD8Fu, 0xCDECu, 0xDDCDu, 0xAD2Au, 0xBD0Bu, 0x8D68u, 0x9D49u,
    0x7E97u, 0x6EB6u, 0x5ED5u, 0x4EF4u, 0x3E13u, 0x2E32u, 0x1E51u, 0x0E70u,
    0xFF9Fu, 0xEFBEu, 0xDFDDu, 0xCFFCu, 0xBF1Bu, 0xAF3Au, 0x9F59u, 0x8F78u,
    0x9188u, 0x81A9u, 0xB1CAu, 0xA1EBu, 0xD10Cu, 0xC12Du, 0xF14Eu, 0xE16Fu,
    0x1080u, 0x00A1u, 0x30C2u, 0x20E3u, 0x5004u, 0x4025u, 0x7046u, 0x6067u,
    0x83B9u, 0x9398u, 0xA3FBu, 0xB3DAu, 0xC33Du, 0xD31Cu, 0xE37Fu, 0xF35Eu,
    0x02B1u, 0x1290u, 0x22F3u, 0x32D2u, 0x4235u, 0x5214u, 0x6277u, 0x7256u,
    0xB5EAu, 0xA5CBu, 0x95A8u, 0x8589u, 0xF56Eu, 0xE54Fu, 0xD52Cu, 0xC50Du,
    0x34E2u, 0x24C3u, 0x14A0u, 0x0481u, 0x7466u, 0x6447u, 0x5424u, 0x4405u,
    0xA7DBu, 0xB7FAu, 0x8799u, 0x97B8u, 0xE75Fu, 0xF77Eu, 0xC71Du, 0xD73Cu,
    0x26D3u, 0x36F2u, 0x0691u, 0x16B0u, 0x6657u, 0x7676u, 0x4615u, 0x5634u,
    0xD94Cu, 0xC96Du, 0xF90Eu, 0xE92Fu, 0x99C8u, 0x89E9u, 0xB98Au, 0xA9ABu,
    0x5844u, 0x4865u, 0x7806u, 0x6827u, 0x18C0u, 0x08E1u, 0x3882u, 0x28A3u,
    0xCB7Du, 0xDB5Cu, 0xEB3Fu, 0xFB1Eu, 0x8BF9u, 0x9BD8u, 0xABBBu, 0xBB9Au,
    0x4A75u, 0x5A54u, 0x6A37u, 0x7A16u, 0x0AF1u, 0x1AD0u, 0x2AB3u, 0x3A92u,
    0xFD2Eu, 0xED0Fu, 0xDD6Cu, 0xCD4Du, 0xBDAAu, 0xAD8Bu, 0x9DE8u, 0x8DC9u,
    0x7C26u, 0x6C07u, 0x5C64u, 0x4C45u, 0x3CA2u, 0x2C83u, 0x1CE0u, 0x0CC1u,
    0xEF1Fu, 0xFF3Eu, 0xCF5Du, 0xDF7Cu, 0xAF9Bu, 0xBFBAu, 0x8FD9u, 0x9FF8u,
    0x6E17u, 0x7E36u, 0x4E55u, 0x5E74u, 0x2E93u, 0x3EB2u, 0x0ED1u, 0x1EF0u
};

/* HKG CAN FD: the final XOR of the 8-, 16-, 24- and 32-byte frames (others: 0). */
#define HKG_XOR_8 0x5F29u
#define HKG_XOR_16 0x041Du
#define HKG_XOR_24 0x819Du
#define HKG_XOR_32 0x9F5Bu

/* Ford: the two messages whose checksum is known, and its byte in each. */
#define FORD_BRAKESYSFEATURES 0x415u
#define FORD_BRAKESYSFEATURES_BYTE 3u
#define FORD_YAW_DATA_FD1 0x91u
#define FORD_YAW_DATA_FD1_BYTE 4u

static const char *const CSUM_NAMES[GRIP_CAN_CSUM_COUNT] = {
    "none", "toyota", "honda", "hkg_can_fd", "hyundai", "hyundai_whl_spd", "volkswagen_mqb",
    "subaru", "chrysler", "fca_giorgio", "nissan", "ford", "xor"
};

const char *grip_can_checksum_name(uint32_t checksum)
{
    return (checksum < (uint32_t)GRIP_CAN_CSUM_COUNT) ? CSUM_NAMES[checksum] : NULL;
}

static uint32_t bare_id(uint32_t id)
{
    return ((id & GRIP_CAN_ID_EFF) != 0u) ? (id & GRIP_CAN_EFF_MASK) : (id & GRIP_CAN_SFF_MASK);
}

/* Lowest payload bit (8 * byte + bit) of a field of `length` bits that is
 * contiguous within one byte or runs over whole bytes: Intel fields start
 * at their lowest bit; a Motorola field's start is its highest bit. */
static uint32_t field_low_bit(const grip_can_message_t *m)
{
    uint32_t start = m->checksum_start;
    uint32_t length = m->checksum_length;
    if (m->checksum_order == (uint8_t)GRIP_CAN_INTEL || length == 0u) {
        return start;
    }
    if (length <= 8u) {
        return start + 1u - length;   /* within one byte (checked by can_checksum_layout_ok) */
    }
    return start - 7u;                /* whole bytes: the first one's bit 0 */
}

/* Is the checksum field one whole byte? Returns its index in *byte. */
static int whole_byte(const grip_can_message_t *m, uint32_t *byte)
{
    uint32_t s = m->checksum_start;
    *byte = s >> 3;
    if (m->checksum_length != 8u) {
        return 0;
    }
    if (m->checksum_order == (uint8_t)GRIP_CAN_INTEL) {
        return (s & 7u) == 0u;
    }
    return (s & 7u) == 7u;
}

int can_checksum_layout_ok(const grip_can_message_t *m)
{
    uint32_t len = m->len;
    uint32_t byte = 0u;
    uint32_t low;
    int ok = 0;
    int is_byte;

    if (m->checksum == (uint8_t)GRIP_CAN_CSUM_NONE) {
        return 1;
    }
    if (m->checksum >= (uint8_t)GRIP_CAN_CSUM_COUNT || m->checksum_order > (uint8_t)GRIP_CAN_MOTOROLA ||
        len == 0u || m->checksum_length == 0u || m->checksum_length > 16u) {
        return 0;
    }
    is_byte = whole_byte(m, &byte);
    low = field_low_bit(m);
    switch (m->checksum) {
    case GRIP_CAN_CSUM_TOYOTA:
    case GRIP_CAN_CSUM_XOR:
        if (is_byte != 0 && byte < len) {
            ok = 1;
        }
        break;
    case GRIP_CAN_CSUM_HONDA:
        if (m->checksum_length == 4u && low == 8u * (len - 1u) &&
            (m->checksum_order == (uint8_t)GRIP_CAN_INTEL || (m->checksum_start & 7u) == 3u)) {
            ok = 1;
        }
        break;
    case GRIP_CAN_CSUM_HKG_CAN_FD:
        if (m->checksum_length == 16u && m->checksum_order == (uint8_t)GRIP_CAN_INTEL &&
            m->checksum_start == 0u && len >= 2u) {
            ok = 1;
        }
        break;
    case GRIP_CAN_CSUM_HYUNDAI:
        if (m->checksum_length == 4u && (low & 3u) == 0u && low + 4u <= 8u * len &&
            (m->checksum_order == (uint8_t)GRIP_CAN_INTEL || (m->checksum_start & 3u) == 3u)) {
            ok = 1;
        }
        break;
    case GRIP_CAN_CSUM_HYUNDAI_WHL_SPD:
        if (len == 8u && m->checksum_length == 2u && m->checksum_order == (uint8_t)GRIP_CAN_INTEL &&
            m->checksum_start == 46u) {
            ok = 1;
        }
        break;
    case GRIP_CAN_CSUM_VOLKSWAGEN_MQB:
    case GRIP_CAN_CSUM_SUBARU:
        if (is_byte != 0 && byte == 0u && len >= 2u) {
            ok = 1;
        }
        break;
    case GRIP_CAN_CSUM_CHRYSLER:
    case GRIP_CAN_CSUM_FCA_GIORGIO:
    case GRIP_CAN_CSUM_NISSAN:
        if (is_byte != 0 && byte == len - 1u) {
            ok = 1;
        }
        break;
    case GRIP_CAN_CSUM_FORD:
        if (is_byte != 0 && len == 8u &&
            ((bare_id(m->id) == FORD_BRAKESYSFEATURES && byte == FORD_BRAKESYSFEATURES_BYTE) ||
            (bare_id(m->id) == FORD_YAW_DATA_FD1 && byte == FORD_YAW_DATA_FD1_BYTE))) {
            ok = 1;
        }
        break;
    default:
        break;
    }
    return ok;
}

static uint32_t crc8(const uint8_t *table, uint32_t init, const uint8_t *data, uint32_t from, uint32_t to)
{
    uint32_t c = init & 0xFFu;
    uint32_t i;
    for (i = from; i < to && i < GRIP_CAN_MAX_DATA; i++) {
        c = table[(c ^ data[i]) & 0xFFu];
    }
    return c;
}

static uint32_t crc16_byte(uint32_t c, uint32_t b)
{
    return ((c << 8) & 0xFFFFu) ^ (uint32_t)CRC16_1021[((c >> 8) ^ b) & 0xFFu];
}

/* Sum of the bytes of the id (Toyota, Subaru). */
static uint32_t id_byte_sum(uint32_t id)
{
    return (id & 0xFFu) + ((id >> 8) & 0xFFu) + ((id >> 16) & 0xFFu) + (id >> 24);
}

static uint32_t honda(uint32_t id, uint32_t ext, const uint8_t *data, uint32_t len)
{
    uint32_t s = 0u;
    uint32_t a = id;
    uint32_t i;
    for (i = 0u; i < 8u; i++) {   /* the nibbles of a 29-bit id */
        s += a & 0xFu;
        a >>= 4;
    }
    for (i = 0u; i < len && i < GRIP_CAN_MAX_DATA; i++) {
        s += (uint32_t)data[i] >> 4;
        if (i + 1u < len) {
            s += (uint32_t)data[i] & 0xFu;   /* the last byte's low nibble is the checksum */
        }
    }
    return (8u - s + ((ext != 0u) ? 3u : 0u)) & 0xFu;
}

static uint32_t hyundai_nibbles(const uint8_t *data, uint32_t len, uint32_t skip_bit)
{
    uint32_t s = 0u;
    uint32_t i;
    for (i = 0u; i < len && i < GRIP_CAN_MAX_DATA; i++) {
        if (8u * i != skip_bit) {
            s += (uint32_t)data[i] & 0xFu;
        }
        if (8u * i + 4u != skip_bit) {
            s += (uint32_t)data[i] >> 4;
        }
    }
    return (16u - (s & 0xFu)) & 0xFu;
}

static uint32_t hyundai_whl_spd(const uint8_t *data)
{
    uint32_t count = 0u;
    uint32_t i;
    uint32_t j;
    for (i = 0u; i < 8u; i++) {
        uint32_t b = data[i];
        if ((i & 1u) != 0u) {
            b &= 0x3Fu;   /* bits 6-7 of bytes 1, 3, 5, 7: counter and checksum */
        }
        for (j = 0u; j < 8u; j++) {
            count += (b >> j) & 1u;
        }
    }
    return (count ^ 9u) & 0xFu;
}

static uint32_t ford(uint32_t id, const uint8_t *data)
{
    uint32_t s;
    if (id == FORD_BRAKESYSFEATURES) {
        /* speed (bytes 0-1), quality flag (byte 2 bits 6-7), counter (byte 2 bits 2-5) */
        s = (uint32_t)data[0] + data[1] + ((uint32_t)data[2] >> 6) + (((uint32_t)data[2] >> 2) & 0xFu);
    } else {
        /* roll and yaw rate (bytes 0-3), counter (byte 5), quality flags (byte 6 bits 4-7) */
        s = (uint32_t)data[0] + data[1] + data[2] + data[3] + data[5] + ((uint32_t)data[6] >> 6) +
            (((uint32_t)data[6] >> 4) & 0x3u);
    }
    return (0xFFu - (s & 0xFFu)) & 0xFFu;
}

uint32_t grip_can_checksum_compute(const grip_can_message_t *m, const uint8_t *data, uint32_t len)
{
    uint32_t id;
    uint32_t byte = 0u;
    uint32_t v = 0u;
    uint32_t i;

    if (m == NULL || data == NULL || len > GRIP_CAN_MAX_DATA || len != m->len || !can_checksum_layout_ok(m)) {
        return 0u;
    }
    id = bare_id(m->id);
    (void)whole_byte(m, &byte);
    switch (m->checksum) {
    case GRIP_CAN_CSUM_TOYOTA:
        v = grip_can_toyota_checksum(id, data, len, byte);
        break;
    case GRIP_CAN_CSUM_HONDA:
        v = honda(id, m->id & GRIP_CAN_ID_EFF, data, len);
        break;
    case GRIP_CAN_CSUM_HKG_CAN_FD:
        for (i = 2u; i < len && i < GRIP_CAN_MAX_DATA; i++) {
            v = crc16_byte(v, data[i]);
        }
        v = crc16_byte(v, id & 0xFFu);
        v = crc16_byte(v, (id >> 8) & 0xFFu);
        if (len == 8u) {
            v ^= HKG_XOR_8;
        } else if (len == 16u) {
            v ^= HKG_XOR_16;
        } else if (len == 24u) {
            v ^= HKG_XOR_24;
        } else if (len == 32u) {
            v ^= HKG_XOR_32;
        } /* grip-deviation: MISRA-15.7 other lengths have no final XOR */
        break;
    case GRIP_CAN_CSUM_HYUNDAI:
        v = hyundai_nibbles(data, len, field_low_bit(m));
        break;
    case GRIP_CAN_CSUM_HYUNDAI_WHL_SPD:
        v = hyundai_whl_spd(data);
        break;
    case GRIP_CAN_CSUM_VOLKSWAGEN_MQB:
        v = crc8(CRC8_2F, 0xFFu, data, 1u, len);
        v = CRC8_2F[(v ^ m->magic[data[1] & 0x0Fu]) & 0xFFu];
        v ^= 0xFFu;
        break;
    case GRIP_CAN_CSUM_SUBARU:
        v = id_byte_sum(id);
        for (i = 1u; i < len && i < GRIP_CAN_MAX_DATA; i++) {
            v += data[i];
        }
        v &= 0xFFu;
        break;
    case GRIP_CAN_CSUM_CHRYSLER:
        v = crc8(CRC8_1D, 0xFFu, data, 0u, len - 1u) ^ 0xFFu;
        break;
    case GRIP_CAN_CSUM_FCA_GIORGIO:
        v = crc8(CRC8_1D, 0x00u, data, 0u, len - 1u) ^ m->magic[0];
        break;
    case GRIP_CAN_CSUM_NISSAN:
        v = crc8(CRC8_1D, 0x00u, data, 0u, len - 1u) ^ 0xFFu;
        break;
    case GRIP_CAN_CSUM_FORD:
        v = ford(id, data);
        break;
    case GRIP_CAN_CSUM_XOR:
        for (i = 0u; i < len && i < GRIP_CAN_MAX_DATA; i++) {
            if (i != byte) {
                v ^= data[i];
            }
        }
        break;
    default:
        v = 0u;
        break;
    }
    return v;
}

uint32_t grip_can_checksum_received(const grip_can_message_t *m, const uint8_t *data, uint32_t len)
{
    uint64_t raw = 0u;
    if (m == NULL || data == NULL || len > GRIP_CAN_MAX_DATA || m->checksum == (uint8_t)GRIP_CAN_CSUM_NONE) {
        return 0u;
    }
    if (m->checksum == (uint8_t)GRIP_CAN_CSUM_HYUNDAI_WHL_SPD) {
        return (len == 8u) ? ((((uint32_t)data[7] >> 6) << 2) | ((uint32_t)data[5] >> 6)) : 0u;
    }
    if (grip_can_extract(data, len, m->checksum_start, m->checksum_length, m->checksum_order, 0u, &raw) != GRIP_OK) {
        return 0u;
    }
    return (uint32_t)raw;
}
