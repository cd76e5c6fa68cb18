/*
 * Wire format 2, the array side: COBS framing, CRC-16/CCITT-FALSE, frame / hello / query
 * messages in, info / status answers out, the watchdog and the counters; and the scheduled-frame
 * extension: timed frames played at their time on the array's clock from a small queue, and the
 * clock exchange the host keeps the array's clock with.
 *
 * Portable C99 with no I/O and no allocation: the same file is compiled for the ATmega2560
 * (firmware/src/main.c) and for the host (firmware/host/shim.c, driven by the test suite with
 * the same test vectors as the Python receiver, tactile_core/device/array.py). Times are the
 * array's clock in microseconds, a uint32_t that wraps every 71.6 minutes; every comparison is
 * a signed difference, so the wrap is harmless.
 */
#ifndef TACTILE_PROTOCOL_H
#define TACTILE_PROTOCOL_H

#include <stddef.h>
#include <stdint.h>

#define TP_VERSION 2
#define TP_MAX_CHANNELS 255
#define TP_MAX_MESSAGE 300 /* encoded bytes buffered; a longer message is dropped ("length") */
#define TP_MAX_REPLY 96    /* an info with a 64-character name is 81 bytes on the wire */
#define TP_NAME_MAX 64

/* The scheduled-frame queue: TP_QUEUE timed frames of up to TP_QUEUE_CHANNELS channels. An array
 * with more channels than that does not announce the extension. */
#ifndef TP_QUEUE
#define TP_QUEUE 24
#endif
#ifndef TP_QUEUE_CHANNELS
#define TP_QUEUE_CHANNELS 30
#endif

enum { TP_FRAME = 0x46, TP_HELLO = 0x48, TP_QUERY = 0x51, TP_INFO = 0x49, TP_STATUS = 0x53,
       TP_TIMED = 0x54, TP_CLOCK = 0x43, TP_CLOCK_REPLY = 0x63 };

/* Feature bits of the info's extension byte. */
enum { TP_FEATURE_SCHEDULED = 0x01 };

/* Why a message was dropped (the Python side's REASONS, in the same order). */
enum { TP_DROP_COBS, TP_DROP_SHORT, TP_DROP_CRC, TP_DROP_TYPE, TP_DROP_LENGTH, TP_DROP_RANGE,
       TP_DROP_REASONS };

/* What tp_feed did with the byte. */
enum { TP_NONE = 0, TP_APPLIED = 1, TP_REPLY = 2, TP_DROPPED = 3, TP_QUEUED = 4, TP_CLOCK_ASKED = 5 };

typedef struct {
    uint8_t cols, rows, levels;
    uint16_t watchdog_ms;
    uint16_t pwm_hz;
    const char *name; /* ASCII, at most TP_NAME_MAX characters */
} tp_config;

typedef struct {
    uint32_t at_us; /* when to play, on the array's clock */
    uint8_t seq;
    uint8_t levels[TP_QUEUE_CHANNELS];
} tp_timed;

typedef struct {
    tp_config cfg;
    uint16_t channels;
    uint8_t scheduled; /* the extension is on (channels fit the queue) */
    uint8_t bits;      /* bits a level takes in a timed frame: enough for levels - 1 */
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
    uint32_t last_valid_us;
    tp_timed queue[TP_QUEUE]; /* timed frames waiting for their time, oldest first */
    uint8_t q_head, q_count;
    uint32_t late;            /* timed frames played after their time */
    uint32_t full;            /* timed frames dropped because the queue was full */
    uint8_t clock_seq;        /* the pending clock request: its seq and arrival time */
    uint32_t clock_rx_us;
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

/* One received byte at time now_us (for a delimiter: when it arrived). TP_APPLIED: a frame
 * replaced s->levels (and flushed the queue of timed frames); TP_QUEUED: a timed frame joined the
 * queue; TP_REPLY: an answer waits in s->reply (s->reply_len bytes); TP_CLOCK_ASKED: the host
 * asked for the clock, answer with tp_clock_reply; TP_DROPPED: a malformed message was counted. */
int tp_feed(tp_state *s, uint8_t byte, uint32_t now_us);

/* Seal the answer to the pending clock request in s->reply, stamped tx_us: the array's clock
 * when its first byte goes out. */
void tp_clock_reply(tp_state *s, uint32_t tx_us);

/* The oldest waiting timed frame, or NULL. */
const tp_timed *tp_head(const tp_state *s);

/* The head timed frame started playing: it becomes s->levels; late if after its time. */
void tp_played(tp_state *s, uint8_t late);

/* Drop every waiting timed frame. */
void tp_flush(tp_state *s);

/* Turn every tactor off (and drop the waiting timed frames) once more than watchdog_ms have
 * passed without a valid frame; 1 if it fired with something on (a trip, counted). */
int tp_watchdog(tp_state *s, uint32_t now_us);

#endif
