/* Wire format 2, the array side, and the scheduled-frame extension. See protocol.h and
 * docs/device.md. */
#include "protocol.h"

#include <string.h>

uint16_t tp_crc16(const uint8_t *data, size_t n)
{
    uint16_t crc = 0xFFFF;
    while (n--) {
        crc ^= (uint16_t)(*data++) << 8;
        for (uint8_t i = 0; i < 8; i++)
            crc = (crc & 0x8000) ? (uint16_t)((crc << 1) ^ 0x1021) : (uint16_t)(crc << 1);
    }
    return crc;
}

int tp_cobs_decode(const uint8_t *in, size_t n, uint8_t *out, size_t out_max)
{
    size_t i = 0, o = 0;
    while (i < n) {
        uint8_t code = in[i++];
        if (code == 0 || i + code - 1 > n)
            return -1;
        for (uint8_t k = 1; k < code; k++) {
            if (o >= out_max)
                return -1;
            out[o++] = in[i++];
        }
        if (code != 0xFF && i < n) {
            if (o >= out_max)
                return -1;
            out[o++] = 0;
        }
    }
    return (int)o;
}

size_t tp_cobs_encode(const uint8_t *in, size_t n, uint8_t *out)
{
    size_t code_at = 0, o = 1;
    uint8_t code = 1;
    for (size_t i = 0; i < n; i++) {
        if (in[i] == 0) {
            out[code_at] = code;
            code_at = o++;
            code = 1;
        } else {
            out[o++] = in[i];
            if (++code == 0xFF) {
                out[code_at] = code;
                code_at = o++;
                code = 1;
            }
        }
    }
    out[code_at] = code;
    out[o++] = 0;
    return o;
}

void tp_init(tp_state *s, const tp_config *cfg)
{
    memset(s, 0, sizeof *s);
    s->cfg = *cfg;
    s->channels = (uint16_t)cfg->cols * cfg->rows;
    s->scheduled = s->channels <= TP_QUEUE_CHANNELS;
    s->bits = 1;
    while ((1u << s->bits) < cfg->levels)
        s->bits++;
}

/* Level c of a bit string of levels `bits` wide, most significant bit first. */
static uint8_t unpack(const uint8_t *data, uint16_t c, uint8_t bits)
{
    uint16_t at = (uint16_t)(c * bits);
    uint16_t two = (uint16_t)((data[at >> 3] << 8) | data[(at >> 3) + 1]);
    return (uint8_t)((two >> (16 - bits - (at & 7))) & ((1u << bits) - 1));
}

const tp_timed *tp_head(const tp_state *s)
{
    return s->q_count ? &s->queue[s->q_head] : NULL;
}

void tp_played(tp_state *s, uint8_t late)
{
    if (!s->q_count)
        return;
    const tp_timed *t = &s->queue[s->q_head];
    memcpy(s->levels, t->levels, s->channels);
    s->last_seq = t->seq;
    s->frames_applied++;
    if (late)
        s->late++;
    s->q_head = (uint8_t)((s->q_head + 1) % TP_QUEUE);
    s->q_count--;
}

void tp_flush(tp_state *s)
{
    s->q_head = 0;
    s->q_count = 0;
}

static void seal(tp_state *s, uint8_t *body, size_t n)
{
    uint16_t crc = tp_crc16(body, n);
    body[n] = (uint8_t)(crc >> 8);
    body[n + 1] = (uint8_t)crc;
    s->reply_len = (uint8_t)tp_cobs_encode(body, n + 2, s->reply);
}

static void put32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)(v >> 24);
    p[1] = (uint8_t)(v >> 16);
    p[2] = (uint8_t)(v >> 8);
    p[3] = (uint8_t)v;
}

static int drop(tp_state *s, int reason)
{
    s->dropped++;
    s->dropped_by[reason]++;
    return TP_DROPPED;
}

/* A complete message (s->buf, s->len bytes, delimiter removed). */
static int handle(tp_state *s, uint32_t now_us)
{
    uint8_t p[TP_MAX_MESSAGE];
    int n = tp_cobs_decode(s->buf, s->len, p, sizeof p);
    if (n < 0)
        return drop(s, TP_DROP_COBS);
    if (n < 4)
        return drop(s, TP_DROP_SHORT);
    uint16_t crc = (uint16_t)((p[n - 2] << 8) | p[n - 1]);
    if (tp_crc16(p, (size_t)n - 2) != crc)
        return drop(s, TP_DROP_CRC);
    int body = n - 2;
    uint8_t type = p[0], seq = p[1];
    if (type == TP_FRAME) {
        if (body < 3 || body != p[2] + 3 || p[2] != s->channels)
            return drop(s, TP_DROP_LENGTH);
        for (int c = 0; c < p[2]; c++)
            if (p[3 + c] >= s->cfg.levels)
                return drop(s, TP_DROP_RANGE);
        memcpy(s->levels, p + 3, p[2]);
        s->frames_applied++;
        s->last_seq = seq;
        s->armed = 1;
        s->last_valid_us = now_us;
        tp_flush(s); /* a frame for now replaces whatever was scheduled */
        return TP_APPLIED;
    }
    if (type == TP_TIMED && s->scheduled) {
        if (body < 7 || body != 7 + (p[6] * s->bits + 7) / 8 || p[6] != s->channels)
            return drop(s, TP_DROP_LENGTH);
        p[n - 2] = 0; /* the CRC's place: the last level may read one byte past the levels */
        for (int c = 0; c < p[6]; c++)
            if (unpack(p + 7, (uint16_t)c, s->bits) >= s->cfg.levels)
                return drop(s, TP_DROP_RANGE);
        s->armed = 1; /* a valid frame feeds the watchdog when it arrives, not when it plays */
        s->last_valid_us = now_us;
        if (s->q_count == TP_QUEUE) {
            s->full++;
            return TP_NONE;
        }
        tp_timed *t = &s->queue[(s->q_head + s->q_count) % TP_QUEUE];
        t->at_us = ((uint32_t)p[2] << 24) | ((uint32_t)p[3] << 16) | ((uint32_t)p[4] << 8) | p[5];
        t->seq = seq;
        for (int c = 0; c < p[6]; c++)
            t->levels[c] = unpack(p + 7, (uint16_t)c, s->bits);
        s->q_count++;
        return TP_QUEUED;
    }
    if (type == TP_CLOCK && s->scheduled) {
        if (body != 2)
            return drop(s, TP_DROP_LENGTH);
        s->clock_seq = seq;
        s->clock_rx_us = now_us;
        return TP_CLOCK_ASKED;
    }
    if (type == TP_HELLO || type == TP_QUERY) {
        if (body != 2)
            return drop(s, TP_DROP_LENGTH);
        uint8_t out[13 + TP_NAME_MAX + 2];
        out[1] = seq;
        if (type == TP_HELLO) {
            size_t len = 0;
            while (s->cfg.name && s->cfg.name[len] && len < TP_NAME_MAX)
                len++;
            out[0] = TP_INFO;
            out[2] = TP_VERSION;
            out[3] = s->cfg.cols;
            out[4] = s->cfg.rows;
            out[5] = s->cfg.levels;
            out[6] = (uint8_t)(s->cfg.watchdog_ms >> 8);
            out[7] = (uint8_t)s->cfg.watchdog_ms;
            out[8] = (uint8_t)(s->cfg.pwm_hz >> 8);
            out[9] = (uint8_t)s->cfg.pwm_hz;
            out[10] = (uint8_t)len;
            memcpy(out + 11, s->cfg.name, len);
            out[11 + len] = s->scheduled ? TP_FEATURE_SCHEDULED : 0; /* the extension */
            out[12 + len] = s->scheduled ? TP_QUEUE : 0;
            seal(s, out, 13 + len);
        } else {
            out[0] = TP_STATUS;
            put32(out + 2, s->frames_applied);
            put32(out + 6, s->dropped);
            out[10] = (uint8_t)(s->watchdog_trips >> 8);
            out[11] = (uint8_t)s->watchdog_trips;
            seal(s, out, 12);
        }
        return TP_REPLY;
    }
    return drop(s, TP_DROP_TYPE); /* info and status are the array's own, unknown types */
}

void tp_clock_reply(tp_state *s, uint32_t tx_us)
{
    uint8_t out[19 + 2];
    out[0] = TP_CLOCK_REPLY;
    out[1] = s->clock_seq;
    put32(out + 2, s->clock_rx_us);
    put32(out + 6, tx_us);
    put32(out + 10, s->late);
    put32(out + 14, s->full);
    out[18] = s->q_count;
    seal(s, out, 19);
}

int tp_feed(tp_state *s, uint8_t byte, uint32_t now_us)
{
    if (byte != 0) {
        if (s->overflow)
            return TP_NONE;
        if (s->len >= TP_MAX_MESSAGE) {
            s->overflow = 1; /* runaway garbage: counted once, at the next delimiter */
            s->len = 0;
            return TP_NONE;
        }
        s->buf[s->len++] = byte;
        return TP_NONE;
    }
    if (s->overflow) {
        s->overflow = 0;
        return drop(s, TP_DROP_LENGTH);
    }
    if (s->len == 0)
        return TP_NONE; /* back-to-back delimiters: nothing was sent */
    int result = handle(s, now_us);
    s->len = 0;
    return result;
}

int tp_watchdog(tp_state *s, uint32_t now_us)
{
    /* More than watchdog_ms on the microsecond clock. */
    if (!s->armed || (uint32_t)(now_us - s->last_valid_us) <= (uint32_t)s->cfg.watchdog_ms * 1000u)
        return 0;
    s->armed = 0;
    tp_flush(s);
    int on = 0;
    for (uint16_t c = 0; c < s->channels; c++)
        on |= s->levels[c];
    memset(s->levels, 0, s->channels);
    if (on)
        s->watchdog_trips++;
    return on != 0;
}
