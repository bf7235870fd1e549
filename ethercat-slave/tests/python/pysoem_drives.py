#!/usr/bin/env python3
"""A real EtherCAT master (SOEM, through pysoem) against `ethercat-node`: a chain of CiA 402 drives
(and other devices) from their ESIs, to Op with Distributed Clocks, each drive axis enabled through
the CiA 402 state machine and moved in cyclic synchronous position mode.

    pysoem_drives.py IFACE UNIT... [--move COUNTS] [--steps N] [--stand-cycles N] [--sync0-ns NS]
                     [--configure-pdos POS] [--assign POS:RX:TX] [--modes] [--csp-claimed]
                     [--sdo-info]

IFACE is the master's interface. Each UNIT describes the unit at that position of the chain as
NAME,VENDOR,PRODUCT,AXES (e.g. "Elmo Drive,0x9a,0x30924,0"): what the master must find there, and
the drive axes it drives, joined by +: CiA 402 axes by number ("0+1" for axes A and B of a
two-axis drive: objects at 0x6000 + 0x800 per axis), MDP 742 channels by m and number ("m0+m1": a
servo or stepper terminal's DRV objects, controlword 0x7n10:01, target position 0x7n10:05, mode
0x7n10:03, statusword 0x6n10:01, position 0x6n00:11 for channel n + 1), "-" for a device that is no
drive. --configure-pdos POS (repeatable) makes the master configure that unit's PDOs itself in
Pre-Op (RxPDO 0x1603 and TxPDO 0x1A01 of the example drive, written by SDO as a configuration tool
does) instead of taking the power-on ones; --assign POS:RX:TX (repeatable) assigns that unit the
PDOs RX (0x1C12) and TX (0x1C13), each a list of mapping objects joined by "," or "=" to keep the
power-on assignment (what a configuration tool takes from the ESI to carry what csp needs).
--modes checks each CiA 402 axis's 0x6502 (supported drive modes) by SDO where the device has the
object (an upload aborted with 0x06020000 says it has none): not 0; --csp-claimed
also requires bit 7 (csp) there. --sdo-info reads each drive's dictionary by SDO Information in
Pre-Op (SOEM's OD list, object and entry descriptions) and checks its identity object and each CiA 402
axis's controlword and statusword in it.

What the script does, as a master that has only the devices (no ESI):
  - config_init: the units' identities from the SII (name, vendor, product code) and 0x1018:01/02,
    serial numbers = positions (1 for the first) in the SII and 0x1018:04;
  - the PDO layout read by SDO (0x1C12/0x1C13 and the mapping objects), as a master without the ESI
    reads it, and from it where each axis's controlword, target position, mode of operation,
    statusword and position actual are in the process data (an entry not mapped is written or read
    by SDO instead);
  - each drive axis's mode of operation 0x6060 = 8 (csp): by SDO in Pre-Op, read back, where the
    RxPDOs do not map it, else in the process data;
  - config_map, config_dc, SYNC0 (1 ms by default) on every drive, Safe-Op, Op, every cycle's
    working counter checked (an answer later than 50 ms is counted and allowed for 1 cycle in 100:
    the machine is shared; a wrong working counter never is);
  - each axis through Shutdown (0x0006), Switch on (0x0007), Enable operation (0x000F) by its
    controlword, the statusword checked at each step (Ready to switch on, Switched on, Operation
    enabled), the target position set to the actual one first;
  - a csp move of each axis from its position by its own distance (the k-th axis overall moves
    (k + 1) × COUNTS, every other one backwards) along a straight ramp of N set-points (--steps,
    1,000 by default), one per cycle, then 0x6064 read back from the process data and by SDO:
    exactly the target, once every axis has held it for 100 cycles in a row (within 5 s), or with
    --stand-cycles N after exactly N cycles standing at the last set-point;
  - during the move every statusword shows Operation enabled without a following error (bit 13),
    the worst 0x60F4 of the axes that map it is reported; at rest 0x60F4 by SDO is 0;
  - every unit in (Op, 0) at the end, then Init.
Every check compares exact values; the first mismatch ends the run with a message on stderr and
exit status 1. Exit status 2: the run could not start. On success one summary line on stdout.
"""

import argparse
import os
import struct
import sys
import time

INIT, PREOP, SAFEOP, OP = 0x01, 0x02, 0x04, 0x08
CSP = 8


class Fail(Exception):
    """A check that did not hold."""


def h(v):
    if isinstance(v, int) and not isinstance(v, bool) and not -10 < v < 10:
        return f"{v} (0x{v & 0xFFFFFFFF:X})"
    return repr(v)


def eq(actual, expected, what):
    if actual != expected:
        raise Fail(f"{what}: expected {h(expected)}, got {h(actual)}")


def u(b):
    return int.from_bytes(b, "little")


def s(b):
    return int.from_bytes(b, "little", signed=True)


class Entry:
    """Where an entry is in a unit's process data: byte offset and length (byte-aligned entries)."""

    def __init__(self, offset, length):
        self.offset = offset
        self.length = length


def sdo_read(slave, index, sub):
    """An SDO upload; one whose mailbox exchange timed out (SOEM's WkcError: the slave's mailbox not
    free within SOEM's time-out, as on a machine busy with other jobs) is tried again, 3 times in
    all. A refusal (an abort) is never tried again."""
    return _retried(lambda: slave.sdo_read(index, sub))


def sdo_write(slave, index, sub, data):
    """An SDO download, tried again as sdo_read is."""
    return _retried(lambda: slave.sdo_write(index, sub, data))


def _retried(call):
    import pysoem

    for attempt in range(3):
        try:
            return call()
        except pysoem.WkcError:
            if attempt == 2:
                raise
            time.sleep(0.05)


def assign(slave, index, pdos):
    """The PDO assignment `index` (0x1C12 or 0x1C13) set to `pdos` by SDO in Pre-Op: ETG.1000.6's
    procedure (count 0, entries, count)."""
    sdo_write(slave, index, 0, b"\x00")
    for k, pdo in enumerate(pdos, start=1):
        sdo_write(slave, index, k, pdo.to_bytes(2, "little"))
    sdo_write(slave, index, 0, bytes([len(pdos)]))


def layout(slave, assign):
    """The mapped entries of an assignment object read by SDO: {(index, sub): Entry}, and the bits."""
    out, bit = {}, 0
    for k in range(1, u(sdo_read(slave, assign, 0)) + 1):
        pdo = u(sdo_read(slave, assign, k))
        for e in range(1, u(sdo_read(slave, pdo, 0)) + 1):
            raw = u(sdo_read(slave, pdo, e))
            index, sub, bits = raw >> 16, (raw >> 8) & 0xFF, raw & 0xFF
            if bit % 8 == 0 and bits % 8 == 0:
                out[(index, sub)] = Entry(bit // 8, bits // 8)
            bit += bits
    return out, bit


class Axis:
    """One drive axis of a unit: where its objects are (a CiA 402 axis's, or an MDP 742 channel's),
    in the process data or by SDO."""

    def __init__(self, unit, slave, axis, outputs, inputs):
        self.unit, self.slave = unit, slave
        self.mdp = axis.startswith("m")
        self.axis = int(axis.lstrip("m"))
        if self.mdp:
            off = 0x100 * self.axis
            self.at = {"cw": (0x7010 + off, 1), "target": (0x7010 + off, 5), "mode": (0x7010 + off, 3),
                       "sw": (0x6010 + off, 1), "pos": (0x6000 + off, 0x11), "display": (0x6010 + off, 3),
                       "ferr": (0x6010 + off, 6), "modes": None}
        else:
            base = 0x6000 + 0x800 * self.axis
            self.at = {"cw": (base + 0x40, 0), "target": (base + 0x7A, 0), "mode": (base + 0x60, 0),
                       "sw": (base + 0x41, 0), "pos": (base + 0x64, 0), "display": (base + 0x61, 0),
                       "ferr": (base + 0xF4, 0), "modes": (base + 0x502, 0)}
        self.cw = outputs.get(self.at["cw"])
        self.target = outputs.get(self.at["target"])
        self.sw = inputs.get(self.at["sw"])
        self.pos = inputs.get(self.at["pos"])
        self.mode = outputs.get(self.at["mode"])
        self.ferr = inputs.get(self.at["ferr"])
        if self.target is None:
            raise Fail(f"{self.name()}: {obj(self.at['target'])} is not in the RxPDOs; csp needs it")

    def name(self):
        kind = "channel" if self.mdp else "axis"
        return f"unit {self.unit} ({self.slave.name}) {kind} {'m' if self.mdp else ''}{self.axis}"

    def read(self, what):
        return sdo_read(self.slave, *self.at[what])

    def write_out(self, entry, value):
        out = bytearray(self.slave.output)
        out[entry.offset:entry.offset + entry.length] = value.to_bytes(entry.length, "little", signed=value < 0)
        self.slave.output = bytes(out)

    def controlword(self, value):
        if self.cw is None:
            sdo_write(self.slave, *self.at["cw"], value.to_bytes(2, "little"))
        else:
            self.write_out(self.cw, value)

    def set_target(self, value):
        self.write_out(self.target, value)

    def statusword(self):
        if self.sw is None:
            return u(self.read("sw"))
        b = bytes(self.slave.input)
        return u(b[self.sw.offset:self.sw.offset + 2])

    def following_error(self):
        """0x60F4 from the process data where it is mapped."""
        if self.ferr is None:
            return None
        b = bytes(self.slave.input)
        return s(b[self.ferr.offset:self.ferr.offset + self.ferr.length])

    def position(self):
        if self.pos is None:
            return s(self.read("pos"))
        b = bytes(self.slave.input)
        return s(b[self.pos.offset:self.pos.offset + self.pos.length])


class Bus:
    """The master and its process-data cycle (~1 ms, single-threaded)."""

    PERIOD = 0.001

    def __init__(self, master):
        self.m = master
        self.next = time.monotonic()
        self.cycles = 0
        self.late = 0

    def cycle(self):
        self.m.send_processdata()
        wkc = self.m.receive_processdata(50_000)
        self.cycles += 1
        if wkc == -1:
            # No answer within 50 ms: a machine too loaded to run the emulator in time (other jobs
            # share it). Counted, and allowed for 1 cycle in 100; a wrong answer never is.
            self.late += 1
            if self.late * 100 > max(self.cycles, 200):
                raise Fail(f"{self.late} of {self.cycles} cycles without an answer within 50 ms")
        elif wkc != self.m.expected_wkc:
            raise Fail(f"cycle {self.cycles}: working counter {wkc}, expected {self.m.expected_wkc}")
        self.next += self.PERIOD
        now = time.monotonic()
        if self.next > now:
            time.sleep(self.next - now)
        else:
            self.next = now

    def run(self, n):
        for _ in range(n):
            self.cycle()

    def until(self, pred, timeout, what, hold=1):
        """Cycles until pred() holds in `hold` cycles in a row."""
        end = time.monotonic() + timeout
        held = 0
        while time.monotonic() < end:
            self.cycle()
            held = held + 1 if pred() else 0
            if held >= hold:
                return
        raise Fail(f"timed out after {timeout} s waiting for {what}")


# CiA 402 statusword states (mask, value).
READY = (0x006F, 0x0021)
SWITCHED_ON = (0x006F, 0x0023)
ENABLED = (0x006F, 0x0027)


def obj(at):
    index, sub = at
    return f"0x{index:04X}" if sub == 0 else f"0x{index:04X}:{sub:02X}"


def in_state(sw, state):
    return sw & state[0] == state[1]


def configure_pdos(slave):
    """The example drive's RxPDO 0x1603 (controlword, target position, profile velocity, mode) and
    TxPDO 0x1A01 remapped to statusword, position actual, mode display, then assigned, by SDO in
    Pre-Op: the procedure of ETG.1000.6 (count 0, entries, count)."""
    sdo_write(slave, 0x1C12, 0, b"\x00")
    sdo_write(slave, 0x1C12, 1, (0x1603).to_bytes(2, "little"))
    sdo_write(slave, 0x1C12, 0, b"\x01")
    sdo_write(slave, 0x1A01, 0, b"\x00")
    for k, raw in enumerate((0x60410010, 0x60640020, 0x60610008), start=1):
        sdo_write(slave, 0x1A01, k, raw.to_bytes(4, "little"))
    sdo_write(slave, 0x1A01, 0, b"\x03")
    sdo_write(slave, 0x1C13, 0, b"\x00")
    sdo_write(slave, 0x1C13, 1, (0x1A01).to_bytes(2, "little"))
    sdo_write(slave, 0x1C13, 0, b"\x01")


def sdo_information(unit, slave, numbers):
    """The dictionary listed and described by SDO Information (SOEM's ecx_readODlist,
    ecx_readODdescription, ecx_readOE): the identity object a RECORD of type IDENTITY (0x0023),
    each CiA 402 axis's controlword and statusword VARs of UNSIGNED16 (0x0006), 16 bits."""
    od = {o.index: o for o in slave.od}
    check(0x1018 in od, f"{unit}: SDO Information lists 0x1018")
    eq((od[0x1018].object_code, od[0x1018].data_type), (9, 0x0023),
       f"{unit}: 0x1018 described as RECORD IDENTITY")
    for a in numbers:
        if a.startswith("m"):
            continue
        base = 0x800 * int(a)
        for index, name in ((0x6040 + base, "controlword"), (0x6041 + base, "statusword")):
            check(index in od, f"{unit}: SDO Information lists 0x{index:04X} ({name})")
            o = od[index]
            eq((o.object_code, o.data_type, o.entries[0].bit_length if o.entries else 16),
               (7, 0x0006, 16), f"{unit}: 0x{index:04X} described as VAR UNSIGNED16")


def check(condition, what):
    if not condition:
        raise Fail(what)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("iface")
    ap.add_argument("units", nargs="+", metavar="NAME,VENDOR,PRODUCT,AXES")
    ap.add_argument("--move", type=int, default=1000)
    ap.add_argument("--steps", type=int, default=1000)
    ap.add_argument("--stand-cycles", type=int, default=None)
    ap.add_argument("--sync0-ns", type=int, default=1_000_000)
    ap.add_argument("--configure-pdos", type=int, action="append", default=[], metavar="POS")
    ap.add_argument("--assign", action="append", default=[], metavar="POS:RX:TX")
    ap.add_argument("--modes", action="store_true")
    ap.add_argument("--csp-claimed", action="store_true")
    ap.add_argument("--sdo-info", action="store_true")
    args = ap.parse_args()
    if args.steps < 1:
        print("cannot run: --steps must be 1 or more", file=sys.stderr)
        return 2
    try:
        import pysoem
    except ImportError as e:
        print(f"cannot run: pysoem is not importable ({e}); pip install pysoem", file=sys.stderr)
        return 2
    if os.geteuid() != 0:
        print("cannot run: a raw-socket EtherCAT master needs root (CAP_NET_RAW)", file=sys.stderr)
        return 2
    expected = []
    for text in args.units:
        name, vendor, product, axes = text.rsplit(",", 3)
        numbers = [] if axes == "-" else axes.split("+")
        expected.append((name, int(vendor, 0), int(product, 0), numbers))
    n = len(expected)
    m = pysoem.Master()
    try:
        m.open(args.iface)
        bus = Bus(m)
        eq(m.config_init(), n, "units config_init found")
        for k, (slave, (name, vendor, product, _)) in enumerate(zip(m.slaves, expected)):
            unit = f"unit {k}"
            # SOEM keeps the first 40 characters of the SII name (EC_MAXNAME).
            eq(slave.name, name[:40], f"{unit}: name (SII)")
            eq((slave.man, slave.id), (vendor, product), f"{unit}: vendor and product code (SII)")
            eq(u(sdo_read(slave, 0x1018, 1)), vendor, f"{unit}: 0x1018:01")
            eq(u(sdo_read(slave, 0x1018, 2)), product, f"{unit}: 0x1018:02")
            # 0x1018:04 where the identity object has it (an ESI may give it three entries).
            if u(sdo_read(slave, 0x1018, 0)) >= 4:
                eq(u(sdo_read(slave, 0x1018, 4)), k + 1, f"{unit}: 0x1018:04 serial number")
            eq(u(slave.eeprom_read(0x0E)), k + 1, f"{unit}: SII serial number")
        m.read_state()
        eq([x.state for x in m.slaves], [PREOP] * n, "every unit in Pre-Op after config_init")
        if args.sdo_info:
            for k, (slave, (_, _, _, numbers)) in enumerate(zip(m.slaves, expected)):
                sdo_information(f"unit {k}", slave, numbers)
        for k in args.configure_pdos:
            configure_pdos(m.slaves[k])
        for text in args.assign:
            pos, rx, tx = text.split(":")
            for index, pdos in ((0x1C12, rx), (0x1C13, tx)):
                if pdos != "=":
                    assign(m.slaves[int(pos)], index, [int(p, 0) for p in pdos.split(",")])
        axes = []
        for k, (slave, (_, _, _, numbers)) in enumerate(zip(m.slaves, expected)):
            outputs, _ = layout(slave, 0x1C12)
            inputs, _ = layout(slave, 0x1C13)
            for a in numbers:
                axis = Axis(k, slave, a, outputs, inputs)
                if args.modes and axis.at["modes"] is not None:
                    where = f"{axis.name()}: {obj(axis.at['modes'])} supported drive modes"
                    try:
                        modes = u(axis.read("modes"))
                    except pysoem.SdoError as e:
                        if e.abort_code != 0x06020000:
                            raise Fail(f"{where}: SDO upload aborted with 0x{e.abort_code:08X} "
                                       f"({e.desc})")
                        # A device without 0x6502 (its ESI lists none): nothing to check; csp is
                        # set by 0x6060 as for every drive.
                        modes = None
                    if modes == 0:
                        raise Fail(f"{where} is 0")
                    if args.csp_claimed and modes is not None and not modes & 1 << 7:
                        raise Fail(f"{where} 0x{modes:08X} lacks csp (bit 7), which the ESI claims")
                if axis.mode is None:
                    # Not in the RxPDOs: csp by SDO (where it is mapped, by the process data).
                    sdo_write(slave, *axis.at["mode"], bytes([CSP]))
                    eq(s(axis.read("mode")), CSP, f"{axis.name()}: {obj(axis.at['mode'])} read back")
                axes.append(axis)
        m.manual_state_change = True
        size = m.config_map()
        if not m.config_dc():
            raise Fail("config_dc found no Distributed Clocks")
        for slave, (_, _, _, numbers) in zip(m.slaves, expected):
            # SYNC0 on the drives; a device that is no drive runs without it.
            if numbers:
                slave.dc_sync(True, args.sync0_ns)
        for slave in m.slaves:
            # The SyncManager watchdog at 1 s (the ESI's 100 ms by default): this master is a script
            # on a machine that may be busy with other jobs, and may pause longer than a PLC.
            slave.set_watchdog("processdata", 1000)
        m.state = SAFEOP
        m.write_state()
        end = time.monotonic() + 2
        while True:
            m.read_state()
            got = [(x.state, x.al_status) for x in m.slaves]
            if got == [(SAFEOP, 0)] * n:
                break
            if time.monotonic() > end:
                raise Fail(f"Safe-Op: units read (state, AL status code) {got}")
            time.sleep(0.01)
        for axis in axes:
            # csp also in the process data where the mode is mapped (it was set by SDO above).
            if axis.mode is not None:
                axis.write_out(axis.mode, CSP)
        bus.next = time.monotonic()
        bus.run(20)
        m.state = OP
        m.write_state()
        bus.until(lambda: (m.read_state(), all(x.state == OP for x in m.slaves))[1], 2.0, "Op")
        bus.run(20)
        for axis in axes:
            axis.set_target(axis.position())
        for word, state, what in ((0x0006, READY, "Ready to switch on"), (0x0007, SWITCHED_ON, "Switched on"),
                                  (0x000F, ENABLED, "Operation enabled")):
            for axis in axes:
                axis.controlword(word)
            for axis in axes:
                bus.until(lambda a=axis: in_state(a.statusword(), state), 2.0,
                          f"{axis.name()} {what} (statusword 0x{axis.statusword():04X})")
        starts = [axis.position() for axis in axes]
        targets = []
        for k, start in enumerate(starts):
            distance = (k + 1) * args.move * (-1) ** k
            targets.append(start + distance)
        # STEPS set-points, one per cycle: axis k moves (k + 1) × COUNTS.
        steps = args.steps
        worst = 0
        for i in range(1, steps + 1):
            for axis, start, target in zip(axes, starts, targets):
                axis.set_target(start + (target - start) * i // steps)
            bus.cycle()
            for axis in axes:
                sw = axis.statusword()
                if sw & 0x2000 or not in_state(sw, ENABLED):
                    raise Fail(f"{axis.name()}: statusword 0x{sw:04X} during the move "
                               "(a following error, or no longer Operation enabled)")
                error = axis.following_error()
                if error is not None:
                    worst = max(worst, abs(error))
        moved = time.monotonic()
        if args.stand_cycles is not None:
            # Standing at the last set-point for exactly that many cycles, then exactly there.
            bus.run(args.stand_cycles)
            for axis, target in zip(axes, targets):
                eq(axis.position(), target,
                   f"{axis.name()}: 0x6064 {args.stand_cycles} cycles after the last set-point")
        else:
            # At rest: every axis at its target for 100 cycles in a row (a servo that came in late,
            # on a loaded machine, may pass its target by a count before it settles).
            bus.until(lambda: all(a.position() == t for a, t in zip(axes, targets)), 5.0,
                      "every axis at its target: " + ", ".join(f"{a.name()} {a.position()}/{t}" for a, t in zip(axes, targets)),
                      hold=100)
        settle = time.monotonic() - moved
        for axis, target in zip(axes, targets):
            eq(axis.position(), target, f"{axis.name()}: position actual in the process data")
            eq(s(axis.read("pos")), target, f"{axis.name()}: {obj(axis.at['pos'])} by SDO")
            eq(s(axis.read("display")), CSP, f"{axis.name()}: {obj(axis.at['display'])} by SDO")
            try:
                error = s(axis.read("ferr"))
            except pysoem.SdoError:
                error = 0
            eq(error, 0, f"{axis.name()}: {obj(axis.at['ferr'])} following error at rest")
            check = axis.statusword()
            if not in_state(check, ENABLED):
                raise Fail(f"{axis.name()}: statusword 0x{check:04X} after the move, not Operation enabled")
        m.read_state()
        eq([(x.state, x.al_status) for x in m.slaves], [(OP, 0)] * n, "(AL state, code) at the end")
        m.state = INIT
        m.write_state()
    except Fail as e:
        print(f"FAIL: {e}", file=sys.stderr)
        return 1
    except Exception as e:  # pysoem's own errors: a check that did not hold, too
        import traceback

        traceback.print_exc()
        print(f"FAIL: unexpected {type(e).__name__}: {e}", file=sys.stderr)
        return 1
    finally:
        m.close()
    moves = "; ".join(f"{a.slave.name} {'channel m' if a.mdp else 'axis '}{a.axis}: {p:+d} → {t:+d}"
                      for a, p, t in zip(axes, starts, targets))
    print(f"pysoem: {n} units to Op with SYNC0 {args.sync0_ns} ns, {len(axes)} axes enabled, "
          f"csp moves at their targets {settle:.2f} s after the last set-point ({moves}), "
          f"following error at most {worst}; "
          f"{bus.cycles - bus.late} cycles at wkc {m.expected_wkc} ({bus.late} late), "
          f"{size} bytes of process data")
    return 0


if __name__ == "__main__":
    sys.exit(main())
