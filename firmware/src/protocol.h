/*
 * Wire format 2, the array side: COBS framing, CRC-16/CCITT-FALSE, frame / hello / query
 * messages in, info / status answers out, the watchdog and the counters.
 *
 * Portable C99 with no I/O and no allocation: the same file is compiled for the ATmega2560
 * (firmware/src/main.c) and for the host (firmware/host/shim.c, driven by the test suite with
 * the same test vectors as the Python receiver, tactile_core/array.py).
 */
#ifndef TACTILE_PROTOCOL_H
#define TACTILE_PROTOCOL_H

#include <stddef.h>
#include <stdint.h>

#define TP_VERSION 2
#define TP_MAX_CHANNELS 255
#define TP_MAX_MESSAGE 300 /* encoded bytes buffered; a longer message is dropped ("length") */
#define TP_MAX_REPLY 96    /* an info with a 64-character name is 79 bytes on the wire */
#define TP_NAME_MAX 64

enum { TP_FRAME = 0x46, TP_HELLO = 0x48, TP_QUERY = 0x51, TP_INFO = 0x49, TP_STATUS = 0x53 };

/* Why a message was dropped (the Python side's REASONS, in the same order). */
enum { TP_DROP_COBS, TP_DROP_SHORT, TP_DROP_CRC, TP_DROP_TYPE, TP_DROP_LENGTH, TP_DROP_RANGE,
       TP_DROP_REASONS };

/* What tp_feed did with the byte. */
enum { TP_NONE = 0, TP_APPLIED = 1, TP_REPLY = 2, TP_DROPPED = 3 };

typedef struct {
    uint8_t cols, rows, levels;
    uint16_t watchdog_ms;
    uint16_t pwm_hz;
    const char *name; /* ASCII, at most TP_NAME_MAX characters */
} tp_config;

typedef struct {
    tp_config cfg;
    uint16_t channels;
    uint8_t buf[TP_MAX_MESSAGE];
    uint16_t len;
    uint8_t overflow;
    uint8_t levels[TP_MAX_CHANNELS]; /* applied, channel order */
    uint8_t last_seq;
    uint32_t frames_applied;
    uint32_t dropped;
    uint32_t dropped_by[TP_DROP_REASONS];
    uint16_t watchdog_trips;
    uint8_t armed;            /* a valid frame arrived and the watchdog has not fired since */
    uint32_t last_valid_ms;
    uint8_t reply[TP_MAX_REPLY]; /* the pending answer, wire form */
    uint8_t reply_len;
} tp_state;

uint16_t tp_crc16(const uint8_t *data, size_t n);

/* COBS-decode in[0..n) (no delimiter) into out; the decoded length, or -1 if malformed. */
int tp_cobs_decode(const uint8_t *in, size_t n, uint8_t *out, size_t out_max);

/* COBS-encode in[0..n) into out (room for n + n / 254 + 2) and append the 0x00 delimiter;
 * returns the bytes written. */
size_t tp_cobs_encode(const uint8_t *in, size_t n, uint8_t *out);

void tp_init(tp_state *s, const tp_config *cfg);

/* One received byte at time now_ms. TP_APPLIED: a frame replaced s->levels; TP_REPLY: an answer
 * waits in s->reply (s->reply_len bytes); TP_DROPPED: a malformed message was counted. */
int tp_feed(tp_state *s, uint8_t byte, uint32_t now_ms);

/* Turn every tactor off once more than watchdog_ms have passed without a valid frame; 1 if it
 * fired with something on (a trip, counted). */
int tp_watchdog(tp_state *s, uint32_t now_ms);

#endif
