/*
 * Reference firmware of the palm array: an Arduino Mega 2560 (ATmega2560, 16 MHz) receives wire
 * format 2 on UART0 at 115200 baud and drives 30 vibration motors by software PWM at 303 Hz with
 * 23 levels. Plain C with avr-libc; no Arduino core.
 *
 * - Timer1 interrupt at 6666.7 Hz steps through the 22 slots of a PWM period, writing four
 *   ports from a precomputed table (pwm.c); a new table is swapped in only at a period's end
 *   (three tables: playing, waiting, being built).
 * - UART0 receive and transmit run from interrupts through ring buffers; the main loop feeds
 *   received bytes to the parser (protocol.c) and sleeps when there is nothing to do.
 * - The watchdog turns every motor off at once when more than 250 ms have passed since the last
 *   valid frame (250 to 251 ms on the millisecond counter).
 *
 * Pin map (channel = row * 5 + col, row 0 at the bottom): channels 0-7 on PORTA (D22-D29),
 * 8-15 on PORTC (D37-D30), 16-23 on PORTL (D49-D42), 24-29 on PORTK bits 0-5 (A8-A13).
 */
#include <avr/interrupt.h>
#include <avr/io.h>
#include <avr/sleep.h>
#include <util/atomic.h>

#include "config.h"
#include "pins.h"
#include "protocol.h"
#include "pwm.h"

#define CHANNELS (ARRAY_COLS * ARRAY_ROWS)
#define PORTS PIN_PORTS


/* Three tables: the one the timer plays, one waiting for the next period, one being built. A
 * frame that arrives while another waits replaces it; the one playing is never touched. */
#define NONE 0xFF
static uint8_t tables[3][PWM_SLOTS * PORTS];
static volatile uint8_t playing = 0, waiting = NONE;
static volatile uint32_t now_ms;

static volatile uint8_t rx_buf[256], tx_buf[128];
static volatile uint8_t rx_head, rx_tail, tx_head, tx_tail;

ISR(TIMER1_COMPA_vect)
{
    static uint8_t slot, ms_acc;
    const uint8_t *row = tables[playing] + slot * PORTS;
    PORTA = row[0];
    PORTC = row[1];
    PORTL = row[2];
    PORTK = row[3];
    if (++slot == PWM_SLOTS) {
        slot = 0;
        if (waiting != NONE) { /* only between periods: a period never mixes two frames */
            playing = waiting;
            waiting = NONE;
        }
    }
    ms_acc += TICK_US_NUM;
    if (ms_acc >= TICK_US_DEN) {
        ms_acc -= TICK_US_DEN;
        now_ms++;
    }
}

ISR(USART0_RX_vect)
{
    uint8_t byte = UDR0;
    uint8_t next = (uint8_t)(rx_head + 1);
    if (next != rx_tail) { /* a full buffer drops the byte; the CRC then drops its message */
        rx_buf[rx_head] = byte;
        rx_head = next;
    }
}

ISR(USART0_UDRE_vect)
{
    if (tx_tail == tx_head) {
        UCSR0B &= (uint8_t)~_BV(UDRIE0);
        return;
    }
    UDR0 = tx_buf[tx_tail];
    tx_tail = (uint8_t)((tx_tail + 1) & 127);
}

static void send(const uint8_t *data, uint8_t n)
{
    for (uint8_t i = 0; i < n; i++) {
        uint8_t next = (uint8_t)((tx_head + 1) & 127);
        while (next == tx_tail) {
        } /* full: the interrupt drains it */
        tx_buf[tx_head] = data[i];
        tx_head = next;
        UCSR0B |= _BV(UDRIE0);
    }
}

static void show(const uint8_t *levels)
{
    uint8_t free_table;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        free_table = 0;
        while (free_table == playing || free_table == waiting)
            free_table++;
    }
    /* The timer may start playing the waiting table meanwhile; this one stays free. */
    pwm_build(levels, CHANNELS, PINS, PORTS, PWM_SLOTS, tables[free_table]);
    waiting = free_table;
}

/* The watchdog: everything off now, not at the end of the period. */
static void all_off_now(void)
{
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        for (uint8_t i = 0; i < sizeof tables[0]; i++)
            tables[playing][i] = 0;
        waiting = NONE;
        PORTA = PORTC = PORTL = PORTK = 0;
    }
}

static uint32_t millis(void)
{
    uint32_t ms;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) { ms = now_ms; }
    return ms;
}

int main(void)
{
    DDRA = 0xFF;
    DDRC = 0xFF;
    DDRL = 0xFF;
    DDRK = 0x3F;
    PORTA = PORTC = PORTL = PORTK = 0; /* all off before anything else */

    UCSR0A = _BV(U2X0); /* before UBRR0: simavr computes the baud rate when UBRR0 is written */
    UBRR0 = UART_UBRR;
    UCSR0C = _BV(UCSZ01) | _BV(UCSZ00); /* 8N1 */
    UCSR0B = _BV(RXEN0) | _BV(TXEN0) | _BV(RXCIE0);

    TCCR1A = 0;
    TCCR1B = _BV(WGM12) | _BV(CS11); /* CTC, clk / 8 */
    OCR1A = TIMER_TOP;
    TIMSK1 = _BV(OCIE1A);

    static tp_state state;
    static const tp_config config = {ARRAY_COLS, ARRAY_ROWS, ARRAY_LEVELS, WATCHDOG_MS, PWM_HZ,
                                     ARRAY_NAME};
    tp_init(&state, &config);
    set_sleep_mode(SLEEP_MODE_IDLE);
    sei();

    for (;;) {
        while (rx_tail != rx_head) {
            uint8_t byte = rx_buf[rx_tail];
            rx_tail = (uint8_t)(rx_tail + 1);
            int result = tp_feed(&state, byte, millis());
            if (result == TP_APPLIED)
                show(state.levels);
            else if (result == TP_REPLY)
                send(state.reply, state.reply_len);
        }
        if (tp_watchdog(&state, millis()))
            all_off_now();
        cli();
        if (rx_tail == rx_head) { /* nothing to do until the next interrupt */
            sleep_enable();
            sei();
            sleep_cpu();
            sleep_disable();
        }
        sei();
    }
}
