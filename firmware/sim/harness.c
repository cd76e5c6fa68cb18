/*
 * Runs the reference firmware in simavr (a cycle-accurate ATmega2560 at 16 MHz), with UART0
 * bridged to a pseudo-terminal and simulated time paced to the wall clock, and records what a
 * logic analyser on the motor pins would see.
 *
 * The bridge is the harness's own rather than simavr's uart_pty part: it puts the host's bytes
 * on the simulated line one at a time, at the pace simavr's UART takes them (so its receive
 * buffer never overruns), and the log says when each byte arrived. simavr counts 11 bit times
 * per byte (start, 8 data, a parity bit that 8N1 does not have, stop): at the firmware's
 * 117,647 baud a byte takes 1496 cycles (93.5 us) instead of 1360, so the simulated line
 * carries 10,695 bytes (289 palm frames) a second rather than 11,765 (318).
 *
 *   harness FIRMWARE.elf LOG [SECONDS]
 *
 * Prints "pty: PATH" on standard output once the pseudo-terminal is open (simavr's loader
 * prints its own lines before it), then runs until
 * SIGTERM / SIGINT or SECONDS of simulated time. LOG gets one line per event, stamped with the
 * simulated cycle (16 per microsecond):
 *
 *   P cycle port value   a port's pins changed (port 0 PORTA, 1 PORTC, 2 PORTL, 3 PORTK)
 *   R cycle byte         UART0 received a byte (hex)
 *   T cycle byte         UART0 sent a byte (hex)
 *
 * and a last line "E cycle" when the run ends.
 */
#include <fcntl.h>
#include <pty.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "avr_ioport.h"
#include "avr_uart.h"
#include "sim_avr.h"
#include "sim_elf.h"
#include <termios.h>

static FILE *logf;
static avr_t *avr;
static volatile sig_atomic_t stop;
static int master = -1;
static uint8_t inbuf[1 << 16];
static size_t in_head, in_tail; /* bytes read from the pty, not yet on the line */
static int xoff;
static avr_irq_t *uart_in;
#define CYCLES_PER_BYTE 1496 /* simavr: 11 bits of (UBRR0 + 1) * 8 cycles with U2X0 */

static void on_signal(int sig)
{
    (void)sig;
    stop = 1;
}

static void on_port(struct avr_irq_t *irq, uint32_t value, void *param)
{
    (void)irq;
    fprintf(logf, "P %llu %d %u\n", (unsigned long long)avr->cycle, (int)(intptr_t)param,
            value & 0xFF);
}

static void on_uart_out(struct avr_irq_t *irq, uint32_t value, void *param)
{
    (void)irq;
    (void)param;
    uint8_t byte = (uint8_t)value;
    fprintf(logf, "T %llu %02x\n", (unsigned long long)avr->cycle, byte);
    if (write(master, &byte, 1) < 0) { /* no reader on the host side: the byte is lost */
    }
}

static void on_xoff(struct avr_irq_t *irq, uint32_t value, void *param)
{
    (void)irq;
    (void)param;
    xoff = value != 0;
}

static void on_xon(struct avr_irq_t *irq, uint32_t value, void *param)
{
    (void)irq;
    (void)param;
    if (value)
        xoff = 0;
}

/* One byte slot on the line: put the next byte on it, if there is one and room. */
static avr_cycle_count_t line_slot(struct avr_t *a, avr_cycle_count_t when, void *param)
{
    (void)a;
    (void)param;
    if (in_tail != in_head && !xoff) {
        uint8_t byte = inbuf[in_tail++ & (sizeof inbuf - 1)];
        fprintf(logf, "R %llu %02x\n", (unsigned long long)when, byte);
        avr_raise_irq(uart_in, byte);
    }
    return when + CYCLES_PER_BYTE;
}

static double wall(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: harness FIRMWARE.elf LOG [SECONDS]\n");
        return 2;
    }
    double seconds = argc > 3 ? atof(argv[3]) : 0.0;
    elf_firmware_t firmware;
    memset(&firmware, 0, sizeof firmware);
    if (elf_read_firmware(argv[1], &firmware) != 0) {
        fprintf(stderr, "harness: cannot read %s\n", argv[1]);
        return 1;
    }
    strcpy(firmware.mmcu, "atmega2560");
    firmware.frequency = 16000000;
    avr = avr_make_mcu_by_name(firmware.mmcu);
    if (!avr) {
        fprintf(stderr, "harness: simavr knows no atmega2560\n");
        return 1;
    }
    avr_init(avr);
    avr_load_firmware(avr, &firmware);
    avr->log = 0;

    logf = fopen(argv[2], "w");
    if (!logf) {
        perror(argv[2]);
        return 1;
    }
    const char ports[4] = {'A', 'C', 'L', 'K'};
    for (int i = 0; i < 4; i++)
        avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_IOPORT_GETIRQ(ports[i]),
                                               IOPORT_IRQ_PIN_ALL),
                                on_port, (void *)(intptr_t)i);
    uint32_t uart = AVR_IOCTL_UART_GETIRQ('0');
    uart_in = avr_io_getirq(avr, uart, UART_IRQ_INPUT);
    avr_irq_register_notify(avr_io_getirq(avr, uart, UART_IRQ_OUTPUT), on_uart_out, NULL);
    avr_irq_register_notify(avr_io_getirq(avr, uart, UART_IRQ_OUT_XOFF), on_xoff, NULL);
    avr_irq_register_notify(avr_io_getirq(avr, uart, UART_IRQ_OUT_XON), on_xon, NULL);

    int slave;
    char name[128];
    if (openpty(&master, &slave, name, NULL, NULL) < 0) {
        perror("openpty");
        return 1;
    }
    struct termios tio;
    tcgetattr(slave, &tio);
    cfmakeraw(&tio);
    tcsetattr(slave, TCSANOW, &tio);
    tcgetattr(master, &tio);
    cfmakeraw(&tio);
    tcsetattr(master, TCSANOW, &tio);
    fcntl(master, F_SETFL, fcntl(master, F_GETFL) | O_NONBLOCK);
    printf("pty: %s\n", name);
    fflush(stdout);
    /* The line opens once the firmware is past its start-up (clearing .bss, enabling the
     * receiver): bytes the host writes earlier wait in the harness, as in a UART's FIFO. */
    avr_cycle_timer_register(avr, 20000, line_slot, NULL);

    signal(SIGTERM, on_signal);
    signal(SIGINT, on_signal);
    const double hz = 16e6;
    double start = wall();
    uint64_t end_cycle = seconds > 0 ? (uint64_t)(seconds * hz) : 0;
    while (!stop) {
        for (int i = 0; i < 2000; i++) {
            int state = avr_run(avr);
            if (state == cpu_Done || state == cpu_Crashed) {
                fprintf(stderr, "harness: the firmware stopped (state %d)\n", state);
                stop = 1;
                break;
            }
        }
        if (end_cycle && avr->cycle >= end_cycle)
            break;
        if (in_head - in_tail < sizeof inbuf - 4096) { /* take what the host wrote */
            uint8_t chunk[4096];
            ssize_t n = read(master, chunk, sizeof chunk);
            for (ssize_t i = 0; i < n; i++)
                inbuf[in_head++ & (sizeof inbuf - 1)] = chunk[i];
        }
        double ahead = avr->cycle / hz - (wall() - start); /* pace to the wall clock */
        if (ahead > 0.0005)
            usleep((useconds_t)(ahead * 1e6));
    }
    fprintf(logf, "E %llu\n", (unsigned long long)avr->cycle);
    fclose(logf);
    fprintf(stderr, "harness: %.3f s simulated in %.3f s\n", avr->cycle / hz, wall() - start);
    close(slave);
    return 0;
}
