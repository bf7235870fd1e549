#!/usr/bin/env python3
"""A real EtherCAT master (SOEM, through pysoem) against `ethercat-node` running one example I/O
device (examples/io-device.esi.xml: three `Fmmu`, four `Sm` elements): garbage in FMMUs 3..15, then a
master that starts again brings the unit to Op.

    pysoem_fmmus.py IFACE

  - a first master: config_init finds the unit (io-device, vendor 0xABC, product 0x191); the ESC
    information 0x0004/0x0005 read by FPRD is 03 04, the ESI's counts (FMMUs and SyncManagers supported,
    ESC datasheet section II);
  - that master writes FMMUs 3..15 by FPWR (WKC 1 each: the ESC is addressed) with a mapping of
    logical 3..5 (where SOEM puts this unit's inputs) onto 0x1100..0x1102 (the outputs
    SyncManager), read and write, activated (ETG.1000.4 Table 57); FMMUs 3..15 read back as 208 zero
    bytes (reserved registers: the write is not taken);
  - the master is closed; a second one (a fresh context, as after a restart): config_init (SOEM
    zeroes FMMUs 0-2 and SyncManagers 0-3, no more), config_map (3 + 3 bytes, expected WKC 3),
    Safe-Op, Op;
  - in Op the outputs A5 34 12 in every cycle, every working counter 3 (2 for the outputs written,
    1 for the inputs read, ETG.1000.4 §5.4.3) and the inputs 00 00 00; 0x1100..0x1102 read by FPRD
    give A5 34 12; 0x7000:01-08 and 0x7010:01 by SDO give 1 0 1 0 0 1 0 1 and 0x1234; the FMMU
    registers 0x0600..0x06FF read by FPRD: FMMU 0 (logical 0, 3 bytes, bits 0-7, physical 0x1100,
    write, active), FMMU 1 (logical 3, 3 bytes, bits 0-7, physical 0x1180, read, active), then 224
    zero bytes.

Every check compares exact values; the first mismatch ends the run with a message on stderr and
exit status 1. Exit status 2: the run could not start. On success one summary line on stdout.
"""

import os
import sys
import time

INIT, PREOP, SAFEOP, OP = 0x01, 0x02, 0x04, 0x08
NAME, VENDOR, PRODUCT = "io-device", 0xABC, 0x191

# FMMU n (3..15): logical 3, 3 bytes, start bit 0, end bit 7, physical 0x1100 bit 0, read and write,
# activated.
GARBAGE = bytes([0x03, 0x00, 0x00, 0x00, 0x03, 0x00, 0x00, 0x07,
                 0x00, 0x11, 0x00, 0x03, 0x01, 0x00, 0x00, 0x00])
OUTPUTS = bytes([0xA5, 0x34, 0x12])
# FMMU 0 and FMMU 1 as SOEM's config_map sets them for this unit, then 224 zero bytes: FMMU 2 as
# config_init zeroed it, FMMUs 3..15 reserved.
FMMU_REGISTERS = bytes([
    0x00, 0x00, 0x00, 0x00, 0x03, 0x00, 0x00, 0x07, 0x00, 0x11, 0x00, 0x02, 0x01, 0x00, 0x00, 0x00,
    0x03, 0x00, 0x00, 0x00, 0x03, 0x00, 0x00, 0x07, 0x80, 0x11, 0x00, 0x01, 0x01, 0x00, 0x00, 0x00,
]) + bytes(224)


class Fail(Exception):
    """A check that did not hold."""


def eq(actual, expected, what):
    if actual != expected:
        raise Fail(f"{what}: expected {expected!r}, got {actual!r}")


def u(b):
    return int.from_bytes(b, "little")


def find_unit(pysoem, iface):
    """A master on IFACE with config_init done: the one unit, in Pre-Op."""
    m = pysoem.Master()
    m.open(iface)
    eq(m.config_init(), 1, "units config_init found")
    s = m.slaves[0]
    eq((s.name, s.man, s.id), (NAME, VENDOR, PRODUCT), "name, vendor, product code (SII)")
    m.read_state()
    eq((s.state, s.al_status), (PREOP, 0), "(AL state, code) after config_init")
    return m


def wait_state(m, state, cycle=None, timeout=2.0):
    end = time.monotonic() + timeout
    while True:
        if cycle:
            cycle()
        m.read_state()
        got = (m.slaves[0].state, m.slaves[0].al_status)
        if got == (state, 0):
            return
        if time.monotonic() > end:
            raise Fail(f"waiting for state {state}: the unit reads (state, AL status code) {got}")
        time.sleep(0.002)


def run(pysoem, iface):
    m = find_unit(pysoem, iface)
    try:
        s = m.slaves[0]
        eq(s._fprd(0x0004, 2), bytes([0x03, 0x04]), "ESC information 0x0004/0x0005")
        for n in range(3, 16):
            # pysoem raises WkcError when the working counter is not 1.
            s._fpwr(0x0600 + 16 * n, GARBAGE)
        eq(s._fprd(0x0630, 208), bytes(208), "FMMUs 3..15 after the garbage")
    finally:
        m.close()

    m = find_unit(pysoem, iface)
    try:
        s = m.slaves[0]
        m.manual_state_change = True
        eq(m.config_map(), 6, "config_map: process image bytes")
        eq(m.expected_wkc, 3, "expected working counter")
        m.state = SAFEOP
        m.write_state()
        wait_state(m, SAFEOP)
        s.output = OUTPUTS
        wkcs = []

        def cycle():
            m.send_processdata()
            wkcs.append(m.receive_processdata(20_000))
            time.sleep(0.001)

        for _ in range(20):
            cycle()
        m.state = OP
        m.write_state()
        wait_state(m, OP, cycle)
        wkcs.clear()
        for _ in range(50):
            cycle()
        eq(sorted(set(wkcs)), [3], "working counters of 50 cycles in Op")
        eq(bytes(s.input), bytes(3), "inputs")
        eq(s._fprd(0x1100, 3), OUTPUTS, "SM2's buffer 0x1100..0x1102")
        bits = [u(s.sdo_read(0x7000, k)) for k in range(1, 9)]
        eq(bits, [1, 0, 1, 0, 0, 1, 0, 1], "0x7000:01..08")
        eq(u(s.sdo_read(0x7010, 1)), 0x1234, "0x7010:01")
        eq(s._fprd(0x0600, 256), FMMU_REGISTERS, "FMMU registers 0x0600..0x06FF")
        m.read_state()
        eq((s.state, s.al_status), (OP, 0), "(AL state, code) at the end")
        m.state = INIT
        m.write_state()
    finally:
        m.close()
    return (f"pysoem master: {NAME} with garbage in FMMUs 3..15 (not taken) to Op after a "
            f"restart, outputs {OUTPUTS.hex(' ')} taken, working counter 3")


def main():
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    try:
        import pysoem
    except ImportError as e:
        print(f"cannot run: pysoem is not importable ({e}); pip install pysoem", file=sys.stderr)
        return 2
    if os.geteuid() != 0:
        print("cannot run: a raw-socket EtherCAT master needs root (CAP_NET_RAW)", file=sys.stderr)
        return 2
    try:
        print(run(pysoem, sys.argv[1]))
    except (Fail, pysoem.WkcError) as e:
        print(f"FAIL: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
