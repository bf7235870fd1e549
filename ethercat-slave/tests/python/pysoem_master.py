#!/usr/bin/env python3
"""A real EtherCAT master (SOEM, through pysoem) against `smd-ethercat`.

    pysoem_master.py IFACE N [--sync0-too-fast | --hold-op SECONDS]

IFACE is the master's interface, N the number of units `smd-ethercat --units N` emulates on the far
end of the link. Every check compares exact values; the first mismatch ends the run with a message on
stderr and exit status 1. Exit status 2: the run could not start (no pysoem, not root). On success one
summary line is printed on stdout.

Default scenario:
  - before pysoem sends anything, a raw BRD of AL status (0x0130) sees every unit in Init, no error,
    AL status code 0 (SMD-T2-007);
  - config_init finds N units with the ESI's identity (AMCI 0x0AC1, SMD23K-B 0x2301, revision 1) and
    serial numbers 1..N, in the SII and in 0x1018:04 alike;
  - in Pre-Op: SDO uploads (0x1008 as a normal, non-expedited transfer; 0x8010 defaults), downloads
    read back, and the abort codes of the refused ones;
  - config_map (40 bytes per unit) in Pre-Op, config_dc, SYNC0 at 2 ms (SMD-T3-003), Safe-Op, Op;
    the process data at ~1 ms: Enable_Driver, Preset Position, a Relative move per unit that ends
    with Move_Complete exactly at its target;
  - the SyncManager watchdog (SMD-R1-035): no process data for 300 ms drops every unit to Safe-Op
    with the error flag and AL status code 0x001B, the inputs show PreOp_SafeOp and Input_Error; the
    error is acknowledged, the units go back to Op and Reset_Errors clears Input_Error.

--sync0-too-fast (SMD-T3-003): with SYNC0 at 1 ms (and 1.999999 ms, 50.000001 ms) the Safe-Op request
is refused: the units stay in Pre-Op with the error flag and AL status code 0x0036; after an
acknowledgement 50 ms and 2 ms are accepted.

--hold-op SECONDS: the units to Op (SYNC0 2 ms) without the SDO checks; "in Op" is printed on stdout
when they are there (the caller may now load the link), then the process data runs at ~1 ms for
SECONDS with the working counter checked in every cycle and every unit read in (Op, 0) every 100 ms.
"""

import argparse
import collections
import os
import select
import socket
import struct
import sys
import time

ETHERTYPE = 0x88A4
VENDOR_ID = 0x00000AC1
PRODUCT_CODE = 0x00002301
REVISION = 0x00000001
NAME = "SMD23K-B"
PD_BYTES = 20  # per unit and direction

INIT, PREOP, SAFEOP, OP = 0x01, 0x02, 0x04, 0x08
ERROR_FLAG, ACK = 0x10, 0x10
AL_SM_WATCHDOG = 0x001B
AL_SYNC0_CYCLE = 0x0036

# SDO abort codes (od/src/model/abort.rs).
ABORT_READ_ONLY = 0x06010002
ABORT_NO_OBJECT = 0x06020000
ABORT_LENGTH_TOO_HIGH = 0x06070012
ABORT_LENGTH_TOO_LOW = 0x06070013
ABORT_NO_SUBINDEX = 0x06090011

# CMD_word0 / CMD_word1 / STATUS_word0 / STATUS_word1 bits (ds402::smd::indexer).
CMD0_RELATIVE_MOVE = 1 << 1
CMD0_PRESET_POSITION = 1 << 9
CMD0_RESET_ERRORS = 1 << 10
CMD1_ENABLE_DRIVER = 1 << 15
ST0_MOVING_CW, ST0_MOVING_CCW, ST0_STOPPED = 1 << 0, 1 << 1, 1 << 3
ST0_MOVE_COMPLETE = 1 << 7
ST0_POSITION_INVALID = 1 << 10
ST0_INPUT_ERROR = 1 << 11
ST0_COMMAND_ERROR = 1 << 12
ST0_CONFIGURATION_ERROR = 1 << 13
ST0_MODULE_OK = 1 << 14
ST1_PREOP_SAFEOP = 1 << 5
ST1_HEARTBEAT = 1 << 11  # toggles on its own

Outputs = collections.namedtuple(
    "Outputs", "cmd0 cmd1 position velocity acceleration deceleration motor_current jerk"
)
Inputs = collections.namedtuple(
    "Inputs",
    "status0 status1 motor_position encoder_position trapped_encoder_position motor_current jerk",
)
OUTPUTS_FMT = "<HHiIHHHH"
INPUTS_FMT = "<HHiiiHH"


class Fail(Exception):
    """A check that did not hold."""


def h(v):
    if isinstance(v, int) and not isinstance(v, bool) and not -10 < v < 10:
        return f"{v} (0x{v & 0xFFFFFFFF:X})"
    return repr(v)


def eq(actual, expected, what):
    if actual != expected:
        raise Fail(f"{what}: expected {h(expected)}, got {h(actual)}")


def check(cond, what):
    if not cond:
        raise Fail(what)


def le(value, size):
    return value.to_bytes(size, "little", signed=value < 0)


# --- a raw look at the bus before the master touches it ------------------------------------------


def raw_brd(iface, ado, length, timeout=0.5):
    """One BRD on a raw socket of our own: (data, wkc) of the answer, or Fail."""
    s = socket.socket(socket.AF_PACKET, socket.SOCK_RAW, socket.htons(ETHERTYPE))
    try:
        s.bind((iface, ETHERTYPE))
        index = 0x5A
        dg = struct.pack("<BBHHHH", 7, index, 0, ado, length, 0) + bytes(length) + b"\0\0"
        src = bytes([0x02, 0x00, 0x00, 0x00, 0x00, 0x7E])
        frame = b"\xff" * 6 + src + struct.pack(">H", ETHERTYPE)
        frame += struct.pack("<H", len(dg) | 0x1000) + dg
        s.send(frame.ljust(60, b"\0"))
        end = time.monotonic() + timeout
        while True:
            left = end - time.monotonic()
            if left <= 0 or not select.select([s], [], [], left)[0]:
                raise Fail(f"no answer to a raw BRD of 0x{ado:04X} on {iface}")
            pkt, addr = s.recvfrom(2048)
            if addr[2] == socket.PACKET_OUTGOING or len(pkt) < 28 + length:
                continue
            if pkt[7:12] != src[1:] or pkt[17] != index:
                continue
            check(pkt[6] & 0x02, "the answer's source address has the locally-administered bit")
            return pkt[26 : 26 + length], struct.unpack_from("<H", pkt, 26 + length)[0]
    finally:
        s.close()


# --- the process-data loop -----------------------------------------------------------------------


class Bus:
    """The master and its process-data cycle (~1 ms, single-threaded)."""

    PERIOD = 0.001

    def __init__(self, pysoem, master, n):
        self.pysoem = pysoem
        self.m = master
        self.n = n
        self.next = time.monotonic()
        self.cycles = 0
        self.wkc_mismatches = 0

    @property
    def slaves(self):
        return self.m.slaves

    def cycle(self, want_wkc=False):
        self.m.send_processdata()
        # A late answer (a loaded machine) waits up to 20 ms rather than count as lost.
        wkc = self.m.receive_processdata(20_000)
        self.cycles += 1
        if want_wkc and wkc != self.m.expected_wkc:
            self.wkc_mismatches += 1
            raise Fail(
                f"cycle {self.cycles}: working counter {wkc}, expected {self.m.expected_wkc}"
            )
        self.next += self.PERIOD
        now = time.monotonic()
        if self.next > now:
            time.sleep(self.next - now)
        else:
            self.next = now
        return wkc

    def run(self, count, want_wkc=False):
        for _ in range(count):
            self.cycle(want_wkc)

    def until(self, pred, timeout, what, want_wkc=False):
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            self.cycle(want_wkc)
            if pred():
                return
        raise Fail(f"timed out after {timeout} s waiting for {what}")

    def restart_clock(self):
        self.next = time.monotonic()

    def inputs(self, k):
        return Inputs._make(struct.unpack(INPUTS_FMT, bytes(self.slaves[k].input)))

    def set_outputs(self, k, o):
        self.slaves[k].output = struct.pack(OUTPUTS_FMT, *o)

    def states(self):
        """AL status and AL status code of every unit, as read now."""
        self.m.read_state()
        return [(s.state, s.al_status) for s in self.slaves]

    def request(self, state, expect_state, expect_code=0, timeout=2.0, cyclic=True):
        """Requests `state` of every unit; waits until each reads `expect_state` / `expect_code`."""
        for s in self.slaves:
            s.state = state
            s.write_state()
        want = [(expect_state, expect_code)] * self.n
        end = time.monotonic() + timeout
        while True:
            got = self.states()
            if got == want:
                return
            if time.monotonic() > end:
                raise Fail(
                    f"after requesting state {h(state)}: units read (state, AL status code) "
                    f"{[(h(a), h(b)) for a, b in got]}, expected {[(h(a), h(b)) for a, b in want]}"
                )
            if cyclic:
                self.run(5)
            else:
                time.sleep(0.005)


# --- the scenario --------------------------------------------------------------------------------


def target(k):
    return [5000, -2000][k] if k < 2 else (1000 + 250 * k) * (-1) ** k


def sdo_abort(pysoem, slave, what, code, fn):
    try:
        fn()
    except pysoem.SdoError as e:
        eq(e.abort_code, code, f"unit {slave}: abort code of {what}")
        return
    raise Fail(f"unit {slave}: {what} was accepted; expected SDO abort {h(code)}")


def enumerate_units(bus, n):
    m = bus.m
    found = m.config_init()
    eq(found, n, "units config_init found")
    eq(len(m.slaves), n, "len(master.slaves)")
    for k, s in enumerate(m.slaves):
        unit = f"unit {k} (position {k})"
        eq(s.name, NAME, f"{unit}: name")
        eq(s.man, VENDOR_ID, f"{unit}: vendor id")
        eq(s.id, PRODUCT_CODE, f"{unit}: product code")
        eq(s.rev, REVISION, f"{unit}: revision")
        # What SOEM read at enumeration, before its Pre-Op request (SMD-T2-007).
        eq(s.state, INIT, f"{unit}: AL state at enumeration")
        eq(s.al_status, 0, f"{unit}: AL status code at enumeration")
        serial = k + 1
        eq(int.from_bytes(s.eeprom_read(0x0E), "little"), serial, f"{unit}: SII serial number")
        for sub, value, what in [
            (1, VENDOR_ID, "vendor id"),
            (2, PRODUCT_CODE, "product code"),
            (3, REVISION, "revision"),
            (4, serial, "serial number"),
        ]:
            eq(
                int.from_bytes(s.sdo_read(0x1018, sub), "little"),
                value,
                f"{unit}: 0x1018:{sub:02X} ({what})",
            )
    # config_init asks for Pre-Op.
    eq(bus.states(), [(PREOP, 0)] * n, "(AL state, code) of every unit after config_init")


def pre_op_sdo(pysoem, bus):
    sdo_information(bus)
    defaults = {0: 7, 1: 0x0000, 2: 0x0003, 3: 141, 4: 2000, 5: 2048, 6: 50, 7: 10}
    sizes = {0: 1, 1: 2, 2: 2, 3: 4, 4: 2, 5: 2, 6: 2, 7: 2}
    for k, s in enumerate(bus.slaves):
        unit = f"unit {k}"
        # 8 bytes: a normal (non-expedited) upload; the 3-byte strings are expedited.
        eq(s.sdo_read(0x1008, 0), NAME.encode(), f"{unit}: 0x1008 device name")
        eq(s.sdo_read(0x1009, 0), b"n/a", f"{unit}: 0x1009 hardware version")
        eq(s.sdo_read(0x100A, 0), b"n/a", f"{unit}: 0x100A software version")
        for sub, value in defaults.items():
            raw = s.sdo_read(0x8010, sub)
            eq(len(raw), sizes[sub], f"{unit}: length of 0x8010:{sub:02X}")
            eq(int.from_bytes(raw, "little"), value, f"{unit}: 0x8010:{sub:02X} default")
        # Starting_Speed (UDINT, 1..1,999,999 steps/s): a valid value per unit, read back.
        speed = 500 + 100 * k
        s.sdo_write(0x8010, 3, le(speed, 4))
        eq(int.from_bytes(s.sdo_read(0x8010, 3), "little"), speed, f"{unit}: 0x8010:03 read back")
        # Motor_Current 35 (3.5 A) is outside 1..34, but the ESI gives no limits: the download is
        # taken (the unit would flag Configuration_Error); 10 (1.0 A) again afterwards.
        s.sdo_write(0x8010, 7, le(35, 2))
        eq(int.from_bytes(s.sdo_read(0x8010, 7), "little"), 35, f"{unit}: 0x8010:07 read back")
        s.sdo_write(0x8010, 7, le(10, 2))
        eq(int.from_bytes(s.sdo_read(0x8010, 7), "little"), 10, f"{unit}: 0x8010:07 restored")
        # Refused downloads and uploads, with their abort codes.
        for what, code, fn in [
            ("a download to 0x1018:04 (ro)", ABORT_READ_ONLY,
             lambda: s.sdo_write(0x1018, 4, le(99, 4))),
            ("a download to 0x1008 (ro)", ABORT_READ_ONLY,
             lambda: s.sdo_write(0x1008, 0, b"ABCDEFGH")),
            ("a download to 0x8010:00 (ro)", ABORT_READ_ONLY,
             lambda: s.sdo_write(0x8010, 0, b"\x07")),
            ("a download to 0x7000:01 (ro)", ABORT_READ_ONLY,
             lambda: s.sdo_write(0x7000, 1, le(1, 2))),
            ("2 bytes to 0x8010:03 (UDINT)", ABORT_LENGTH_TOO_LOW,
             lambda: s.sdo_write(0x8010, 3, le(600, 2))),
            ("4 bytes to 0x8010:01 (UINT)", ABORT_LENGTH_TOO_HIGH,
             lambda: s.sdo_write(0x8010, 1, le(0, 4))),
            ("a download to 0x8010:09", ABORT_NO_SUBINDEX,
             lambda: s.sdo_write(0x8010, 9, le(0, 2))),
            ("an upload of 0x8010:09", ABORT_NO_SUBINDEX, lambda: s.sdo_read(0x8010, 9)),
            ("an upload of 0x2000", ABORT_NO_OBJECT, lambda: s.sdo_read(0x2000, 0)),
        ]:
            sdo_abort(pysoem, k, what, code, fn)
        # Nothing refused changed anything.
        eq(int.from_bytes(s.sdo_read(0x8010, 3), "little"), speed, f"{unit}: 0x8010:03 kept")
        eq(int.from_bytes(s.sdo_read(0x1018, 4), "little"), k + 1, f"{unit}: 0x1018:04 kept")


def sdo_information(bus):
    """The dictionary listed and described by SDO Information (SOEM's ecx_readODlist,
    ecx_readODdescription, ecx_readOE), as a configuration tool reads it without the ESI."""
    od = {o.index: o for o in bus.slaves[0].od}
    for index in (0x1000, 0x1008, 0x1018, 0x1600, 0x1A00, 0x1C12, 0x1C13, 0x6000, 0x7000, 0x8010):
        check(index in od, f"SDO Information lists 0x{index:04X}")
    eq((od[0x1018].object_code, od[0x1018].data_type, od[0x1018].name), (9, 0x0023, b"Identity"),
       "0x1018 described as RECORD IDENTITY")
    eq((od[0x1008].object_code, od[0x1008].data_type), (7, 0x0009), "0x1008 VAR VISIBLE_STRING")
    cfg = [(e.name, e.data_type, e.bit_length, e.obj_access) for e in od[0x8010].entries]
    eq(cfg[3], (b"Starting_Speed", 0x0007, 32, 0x3F), "0x8010:03 described")
    status = od[0x6000].entries[1]
    eq((status.name, status.data_type, status.bit_length, status.obj_access),
       (b"STATUS_word0", 0x0006, 16, 0x87), "0x6000:01 described (TxPDO-mappable, read-only)")
    command = od[0x7000].entries[1]
    eq((command.name, command.obj_access), (b"CMD_word0", 0x47), "0x7000:01 RxPDO-mappable")


def map_in_pre_op(bus, n):
    m = bus.m
    # SOEM's config_map asks for Safe-Op itself unless told not to: the SYNC0 setting must come first.
    m.manual_state_change = True
    size = m.config_map()
    eq(size, 2 * PD_BYTES * n, "config_map: process image bytes")
    eq(m.expected_wkc, 3 * n, "expected working counter (LRW: 2 per output + 1 per input)")
    for k, s in enumerate(bus.slaves):
        eq(len(bytes(s.output)), PD_BYTES, f"unit {k}: output bytes")
        eq(len(bytes(s.input)), PD_BYTES, f"unit {k}: input bytes")
        eq(s.get_watchdog("processdata"), 100.0, f"unit {k}: process-data watchdog, ms")
    eq(bus.states(), [(PREOP, 0)] * n, "(AL state, code) after config_map")
    check(m.config_dc(), "config_dc found the units' Distributed Clocks")


def sync0(bus, cycle_ns):
    for s in bus.slaves:
        s.dc_sync(True, cycle_ns)


def scenario_sync0_too_fast(bus, n):
    """SMD-T3-003: SYNC0 outside 2..50 ms is refused at Pre-Op -> Safe-Op with 0x0036."""
    refused = []
    for cycle_ns in (1_000_000, 1_999_999, 50_000_001):
        sync0(bus, cycle_ns)
        bus.request(SAFEOP, PREOP | ERROR_FLAG, AL_SYNC0_CYCLE, cyclic=False)
        refused.append(cycle_ns)
        # Acknowledged: Pre-Op, no error, code 0.
        bus.request(PREOP | ACK, PREOP, 0, cyclic=False)
    for cycle_ns in (50_000_000, 2_000_000):
        sync0(bus, cycle_ns)
        bus.restart_clock()
        bus.request(SAFEOP, SAFEOP, 0)
        bus.request(PREOP, PREOP, 0)
    return (
        f"pysoem master: {n} × {NAME}: SYNC0 "
        + ", ".join(f"{c} ns" for c in refused)
        + f" refused (Pre-Op + error, AL status code 0x{AL_SYNC0_CYCLE:04X}); 50 ms and 2 ms accepted"
    )


def scenario_run(bus, n):
    sync0(bus, 2_000_000)
    bus.restart_clock()
    bus.request(SAFEOP, SAFEOP, 0)
    # Safe-Op: inputs flow, outputs are not acted on. From here the process data never stops
    # longer than a cycle until the watchdog test.
    bus.run(20)
    for k in range(n):
        i = bus.inputs(k)
        # Position_Invalid (the configuration was written), Stopped, Module_OK.
        eq(i.status0, ST0_MODULE_OK | ST0_POSITION_INVALID | ST0_STOPPED,
           f"unit {k}: STATUS_word0 in Safe-Op")
        eq(i.status1 & ~ST1_HEARTBEAT, ST1_PREOP_SAFEOP,
           f"unit {k}: STATUS_word1 in Safe-Op (Heartbeat masked)")
        eq(i.motor_current, 10, f"unit {k}: Motor_Current input (0x8010:07)")
        eq(i.motor_position, 0, f"unit {k}: Motor_Position in Safe-Op")

    def drive(cmd0, position=None):
        for k in range(n):
            bus.set_outputs(
                k,
                Outputs(
                    cmd0=cmd0,
                    cmd1=CMD1_ENABLE_DRIVER,
                    position=target(k) if position is None else position,
                    velocity=10_000,
                    acceleration=100,
                    deceleration=100,
                    motor_current=0,
                    jerk=0,
                ),
            )

    drive(0, 0)
    bus.request(OP, OP, 0)
    bus.run(10, want_wkc=True)
    for k in range(n):
        eq(bus.inputs(k).status1 & ST1_PREOP_SAFEOP, 0, f"unit {k}: PreOp_SafeOp in Op")
    drive(CMD0_PRESET_POSITION, 0)
    bus.run(5, want_wkc=True)
    drive(0, 0)
    bus.run(5, want_wkc=True)
    for k in range(n):
        eq(bus.inputs(k).status0 & ST0_POSITION_INVALID, 0, f"unit {k}: Position_Invalid after the preset")
    drive(CMD0_RELATIVE_MOVE)
    started = time.monotonic()
    bus.until(
        lambda: all(bus.inputs(k).status0 & ST0_MOVE_COMPLETE for k in range(n)),
        10.0,
        "Move_Complete on every unit",
        want_wkc=True,
    )
    move_s = time.monotonic() - started
    for k in range(n):
        i = bus.inputs(k)
        eq(i.motor_position, target(k), f"unit {k}: Motor_Position after the Relative move")
        eq(i.status1 & ST1_PREOP_SAFEOP, 0, f"unit {k}: PreOp_SafeOp in Op")
        eq(i.status0 & (ST0_MOVING_CW | ST0_MOVING_CCW), 0, f"unit {k}: moving bits at Move_Complete")
        eq(i.status0 & ST0_STOPPED, ST0_STOPPED, f"unit {k}: Stopped at Move_Complete")
        eq(i.status0 & (ST0_INPUT_ERROR | ST0_COMMAND_ERROR | ST0_CONFIGURATION_ERROR), 0,
           f"unit {k}: error bits after the move")
    eq(bus.states(), [(OP, 0)] * n, "(AL state, code) after the move")

    # SMD-R1-035: no process data for 300 ms (watchdog 100 ms).
    time.sleep(0.3)
    eq(bus.states(), [(SAFEOP | ERROR_FLAG, AL_SM_WATCHDOG)] * n,
       "(AL state, code) after 300 ms without process data")
    bus.restart_clock()
    bus.run(10)
    for k in range(n):
        i = bus.inputs(k)
        eq(i.status1 & ST1_PREOP_SAFEOP, ST1_PREOP_SAFEOP, f"unit {k}: PreOp_SafeOp after the watchdog")
        eq(i.status0 & ST0_INPUT_ERROR, ST0_INPUT_ERROR, f"unit {k}: Input_Error after the watchdog")
        eq(i.motor_position, target(k), f"unit {k}: Motor_Position kept")
    # Still Safe-Op + error while not acknowledged: a plain Op request changes nothing.
    bus.request(OP, SAFEOP | ERROR_FLAG, AL_SM_WATCHDOG, timeout=0.05)
    bus.request(SAFEOP | ACK, SAFEOP, 0)
    drive(0)
    bus.request(OP, OP, 0)
    bus.run(10, want_wkc=True)
    for k in range(n):
        eq(bus.inputs(k).status1 & ST1_PREOP_SAFEOP, 0, f"unit {k}: PreOp_SafeOp back in Op")
    drive(CMD0_RESET_ERRORS)
    bus.run(5, want_wkc=True)
    drive(0)
    bus.until(
        lambda: all(bus.inputs(k).status0 & ST0_INPUT_ERROR == 0 for k in range(n)),
        1.0,
        "Reset_Errors to clear Input_Error",
        want_wkc=True,
    )
    eq(bus.states(), [(OP, 0)] * n, "(AL state, code) at the end")
    targets = "/".join(f"{target(k):+d}" for k in range(n))
    return (
        f"pysoem master: {n} × {NAME} (serials 1..{n}) Init→Pre-Op→Safe-Op (SYNC0 2 ms)→Op; "
        f"SDO checks passed; Relative moves {targets} complete in {move_s:.2f} s; "
        f"{bus.cycles} cycles at wkc {bus.m.expected_wkc}; SM watchdog → Safe-Op+error "
        f"0x{AL_SM_WATCHDOG:04X}, acknowledged, back in Op"
    )


def scenario_hold_op(bus, n, seconds):
    """Op held for `seconds`: every cycle at the expected working counter, (Op, 0) every 100 ms."""
    sync0(bus, 2_000_000)
    bus.restart_clock()
    bus.request(SAFEOP, SAFEOP, 0)
    bus.run(20)
    bus.request(OP, OP, 0)
    bus.run(10, want_wkc=True)
    print("in Op", flush=True)
    start = bus.cycles
    reads = 0
    end = time.monotonic() + seconds
    next_read = time.monotonic()
    while time.monotonic() < end:
        bus.cycle(want_wkc=True)
        if time.monotonic() >= next_read:
            eq(bus.states(), [(OP, 0)] * n, f"(AL state, code) after {bus.cycles - start} cycles in Op")
            reads += 1
            next_read += 0.1
    eq(bus.states(), [(OP, 0)] * n, "(AL state, code) at the end")
    return (
        f"pysoem master: {n} × {NAME} held Op for {seconds:g} s: {bus.cycles - start} cycles, "
        f"wkc {bus.m.expected_wkc} in each, (Op, 0) at {reads + 1} state reads"
    )


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("iface")
    ap.add_argument("units", type=int)
    ap.add_argument("--sync0-too-fast", action="store_true",
                    help="prove the SYNC0 cycle check instead of running the units")
    ap.add_argument("--hold-op", type=float, metavar="SECONDS",
                    help="hold the units in Op for SECONDS instead of the default scenario")
    args = ap.parse_args()
    try:
        import pysoem
    except ImportError as e:
        print(f"cannot run: pysoem is not importable ({e}); pip install pysoem", file=sys.stderr)
        return 2
    if os.geteuid() != 0:
        print("cannot run: a raw-socket EtherCAT master needs root (CAP_NET_RAW)", file=sys.stderr)
        return 2
    n = args.units
    master = None
    try:
        # SMD-T2-007: nothing has asked for a state yet; every unit is in Init.
        data, wkc = raw_brd(args.iface, 0x0130, 6)
        eq(wkc, n, "raw BRD of AL status: working counter")
        eq(data[0], INIT, "raw BRD of AL status: every unit in Init, no error")
        eq(int.from_bytes(data[4:6], "little"), 0, "raw BRD of AL status code")
        master = pysoem.Master()
        master.open(args.iface)
        bus = Bus(pysoem, master, n)
        enumerate_units(bus, n)
        if args.hold_op is None:
            pre_op_sdo(pysoem, bus)
        map_in_pre_op(bus, n)
        if args.hold_op is not None:
            summary = scenario_hold_op(bus, n, args.hold_op)
        elif args.sync0_too_fast:
            summary = scenario_sync0_too_fast(bus, n)
        else:
            summary = scenario_run(bus, n)
        master.state = INIT
        master.write_state()
    except Fail as e:
        print(f"FAIL: {e}", file=sys.stderr)
        return 1
    except Exception as e:  # pysoem's own errors: a check that did not hold, too
        import traceback

        traceback.print_exc()
        print(f"FAIL: unexpected {type(e).__name__}: {e}", file=sys.stderr)
        return 1
    finally:
        if master is not None:
            master.close()
    print(summary)
    return 0


if __name__ == "__main__":
    sys.exit(main())
