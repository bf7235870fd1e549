#!/usr/bin/env python3
"""python-canopen's BaseNode402 as a user drives a CiA 402 node it has only the description of.

    accept402_canopen.py --eds FILE --node-id N (--socketcand HOST:PORT | --socketcan IFACE)
                         [--cycle-ms MS]

The master takes the node as it comes: it reads the node's PDO configuration by SDO
(`setup_402_state_machine`) and changes nothing in it. Where a PDO of the drive is synchronous
(transmission type 0-240) it runs SYNC every --cycle-ms (10 ms by default) and sends the synchronous
RPDOs on that cycle, as python-canopen's documentation has a user do; an object an enabled RPDO maps
is written into the RPDO (sent at once when the RPDO is event-driven), every other one by SDO.

The scenario, each mode only where the node's 0x6502 lists it:
  identity    0x1000 bits 0-15 = 402; 0x1018:01-03 as the description says (its 0x1018 values, else
              [DeviceInfo] VendorNumber/ProductNumber/RevisionNumber)
  state       SWITCH ON DISABLED -> OPERATION ENABLED (node.state); quick stop (control word
              0x0002): QUICK STOP ACTIVE where 0x605A is 5-8, else SWITCH ON DISABLED; then
              SWITCH ON DISABLED and back to OPERATION ENABLED
  homing      where 0x6098 exists: method 35 (the current position is home), node.homing() (the
              handshake by SDO where the status word's TPDO is sent on change only, see homing());
              the position is then the home offset 0x607C
  rtr         on SocketCAN (socketcand carries no remote frames): every enabled TPDO that is not
              sent on every n-th SYNC and allows RTR answers a remote frame with its data
  pp          node.op_mode = "PROFILED POSITION", a move of +2,000 counts by the set-point handshake
              (profile velocity 10,000 counts/s where 0x6081 exists; accelerations as the node has
              them; shorter and slower where the drive's 0x607F, 0x6083, 0x6084 would make it last
              over 2 s); at target reached 0x6064 is exactly the target
  pv          a run at 2,000 counts/s (less where 0x607F or 0x6083 are lower) until velocity
              reached (0x606C within the velocity window 0x606D of it, where the description has
              one), 0x606C then exactly the target, then target velocity 0 until standstill
  csp         100 set-points of +20 counts (less where 0x607F is lower), one per SYNC, then 1 s
              standing: 0x6064 exactly the last one
  end         quick stop, SWITCH ON DISABLED, and no EMCY other than "error reset" during the run
One line per step (`ok`, `SKIP` with why); the first difference ends the run with `FAIL what: …`
and exit status 1. The last line is PASS.
"""

import argparse
import logging
import os
import sys
import time

import canopen
from canopen.profiles.p402 import BaseNode402


class Failed(Exception):
    pass


def ok(what, value=None):
    print(f"ok   {what}" + ("" if value is None else f": {value!r}"), flush=True)


def skip(what, why):
    print(f"SKIP {what}: {why}", flush=True)


def fail(what):
    raise Failed(what)


def check(what, got, want):
    if got != want:
        fail(f"{what}: expected {want!r}, got {got!r}")
    ok(what, got)


def wait_for(what, predicate, timeout):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if predicate():
            ok(what)
            return
        time.sleep(0.01)
    fail(f"{what}: not within {timeout} s")


def expected_identity(od):
    """0x1018:01-03 as the description gives them: the object's values, else [DeviceInfo]."""
    info = od.device_information
    fallback = {1: info.vendor_number, 2: info.product_number, 3: info.revision_number}
    out = {}
    for sub in (1, 2, 3):
        value = None
        if 0x1018 in od and sub in od[0x1018]:
            entry = od[0x1018][sub]
            value = entry.value if entry.value is not None else entry.default
        if value is None:
            value = fallback[sub]
        out[sub] = value
    return out


class Master:
    def __init__(self, args):
        self.args = args
        self.network = canopen.Network()
        if args.socketcan:
            self.network.connect(interface="socketcan", channel=args.socketcan)
        else:
            host, port = args.socketcand.rsplit(":", 1)
            self.network.connect(interface="socketcand", host=host, port=int(port), channel="can0")
        self.node = BaseNode402(args.node_id, args.eds)
        self.network.add_node(self.node)
        self.node.sdo.RESPONSE_TIMEOUT = 2.0
        self.emcy = []
        self.network.subscribe(0x80 + args.node_id,
                               lambda can_id, data, ts: self.emcy.append(bytes(data)))
        self.cycle = args.cycle_ms / 1000.0
        self.sync_running = False
        self.last_target = 0

    def has(self, index):
        return index in self.node.object_dictionary

    def put(self, index, value):
        """Writes a drive object: into every enabled RPDO that maps it (an event-driven one is sent
        at once, a synchronous one carries it with its next cycle), else by SDO."""
        mapped = [(pdo, v) for pdo in self.node.rpdo.values() if pdo.enabled
                  for v in pdo if v.index == index]
        if not mapped:
            self.node.sdo[index].raw = value
            return
        if index == 0x607A:
            self.last_target = value
        control = self.node.rpdo_pointers.get(0x6040)
        for pdo, v in mapped:
            v.raw = value
            # An RPDO carries every object it maps: its copy of the control word is the one
            # BaseNode402 last sent, not the 0 it holds until then.
            for other in pdo:
                if other.index == 0x6040 and control is not None and other is not control:
                    other.raw = control.raw
        pdos = {id(p): p for p, _ in mapped}.values()
        for pdo in pdos:
            if not pdo.is_periodic:
                pdo.transmit()
        if any(pdo.is_periodic for pdo in pdos):
            # Taken at a SYNC after the RPDO's next cycle: go on once the drive has it.
            wait_for(f"0x{index:04X} = {value} through a synchronous RPDO",
                     lambda: self.node.sdo[index].raw == value, 2)

    def synchronous_pdos(self):
        return [pdo for pdo in list(self.node.tpdo.values()) + list(self.node.rpdo.values())
                if pdo.enabled and pdo.trans_type is not None and pdo.trans_type <= 240]

    def start_sync(self):
        if self.sync_running:
            return
        self.network.sync.start(self.cycle)
        for rpdo in self.node.rpdo.values():
            if rpdo.enabled and rpdo.trans_type is not None and rpdo.trans_type <= 240:
                rpdo.start(self.cycle)
                ok(f"RPDO 0x{rpdo.cob_id:03X} sent every {self.args.cycle_ms} ms")
        self.sync_running = True
        ok(f"SYNC every {self.args.cycle_ms} ms")

    def statusword(self):
        return self.node.sdo[0x6041].raw

    def position(self):
        """0x6064, or the last target where the description has no 0x6064 (the master cannot read
        where the drive is)."""
        if not self.has(0x6064):
            return self.last_target
        return self.node.sdo[0x6064].raw

    def check_position(self, what, want):
        if not self.has(0x6064):
            skip(what, "the description has no 0x6064")
            return
        check(what, self.position(), want)

    def writable(self, index):
        access = getattr(self.node.object_dictionary[index], "access_type", "rw")
        return access in ("rw", "wo", "rww", "rwr")

    def run(self):
        node = self.node
        od = node.object_dictionary
        # Identity.
        device_type = node.sdo[0x1000].raw
        check("device type 0x1000 bits 0-15 (CiA 402)", device_type & 0xFFFF, 402)
        want = expected_identity(od)
        for sub, name in [(1, "vendor-ID"), (2, "product code"), (3, "revision number")]:
            if 0x1018 in od and sub not in od[0x1018]:
                skip(f"0x1018:{sub:02X} {name}", "the description's 0x1018 has no such entry")
                continue
            if want[sub] is None:
                skip(f"0x1018:{sub:02X} {name}", "the description gives none")
                continue
            check(f"0x1018:{sub:02X} {name}", node.sdo[0x1018][sub].raw, want[sub])

        node.nmt.state = "PRE-OPERATIONAL"
        node.setup_402_state_machine()
        if self.has(0x6502):
            supported = node.sdo[0x6502].raw
            ok(f"supported drive modes 0x6502 = 0x{supported:08X}")
            if supported == 0:
                fail("0x6502 lists no mode: BaseNode402 can set none")
        else:
            # BaseNode402's op_mode needs 0x6502: a user sets 0x6060 and sees what the drive takes.
            skip("BaseNode402.op_mode", "the description has no 0x6502: 0x6060 written directly")
            supported = self.probe_modes()
        if self.synchronous_pdos():
            self.start_sync()
        node.nmt.state = "OPERATIONAL"
        time.sleep(0.1)

        self.remote_requests()
        node.state = "SWITCH ON DISABLED"
        check("state", node.state, "SWITCH ON DISABLED")
        node.state = "OPERATION ENABLED"
        check("state", node.state, "OPERATION ENABLED")
        check("statusword & 0x6F", self.statusword() & 0x6F, 0x27)
        self.quick_stop()
        node.state = "OPERATION ENABLED"
        check("state", node.state, "OPERATION ENABLED")

        if supported & 0x20:
            method = node.sdo[0x6098].raw if self.has(0x6098) else None
            if method is None:
                skip("homing", "the description has no 0x6098")
            elif not self.writable(0x6098) and method not in (35, 37):
                skip("homing", f"0x6098 is {method}, which the description does not let a master "
                     "change, and the machine has no switches")
            else:
                if self.writable(0x6098):
                    self.put(0x6098, 35)
                self.homing()
                offset = node.sdo[0x607C].raw if self.has(0x607C) else 0
                self.check_position("position after homing on the current position", offset)
        if supported & 0x01:
            self.pp()
        if supported & 0x04:
            self.pv()
        if supported & 0x80:
            self.csp()

        self.quick_stop()
        emcy = [e for e in self.emcy if e[:2] != b"\x00\x00"]
        check("EMCY during the run", [e.hex() for e in emcy], [])

    def remote_requests(self):
        """Every enabled TPDO that allows RTR answers a remote frame with its data (CiA 301)."""
        if not self.args.socketcan:
            skip("remote frames", "socketcand carries no remote frames")
            return
        for pdo in self.node.tpdo.values():
            if not pdo.enabled or not pdo.rtr_allowed:
                continue
            if pdo.trans_type is not None and 1 <= pdo.trans_type <= 240:
                continue  # sent on SYNC anyway
            got = []
            listener = lambda can_id, data, ts: got.append(bytes(data))
            self.network.subscribe(pdo.cob_id, listener)
            time.sleep(0.05)
            before = len(got)
            pdo.remote_request()
            wait_for(f"TPDO 0x{pdo.cob_id:03X} answers a remote frame",
                     lambda: len(got) > before, 1)
            check(f"TPDO 0x{pdo.cob_id:03X} length", len(got[-1]), pdo.length // 8)
            self.network.unsubscribe(pdo.cob_id, listener)

    def mode(self):
        """The mode of operation: node.op_mode, or 0x6061 by SDO where the TPDO that maps it is sent
        on change only (see event_only)."""
        if self.event_only(0x6061) or not self.has(0x6502):
            from canopen.profiles.p402 import OperationMode
            return OperationMode.CODE2NAME[self.node.sdo[0x6061].raw]
        return self.node.op_mode

    def event_only_status(self):
        return self.event_only(0x6041)

    def event_only(self, index):
        """Whether the TPDO BaseNode402 reads `index` from is sent only on a change (event-driven
        without an event timer, or acyclic synchronous). BaseNode402 takes a TPDO it has received twice for a periodic one
        and then waits 0.2 s for the next before it answers node.op_mode or checks the status
        word; a drive that sends on change only sends none while nothing changes."""
        pointer = self.node.tpdo_pointers.get(index)
        if pointer is None:
            return False
        pdo = pointer.pdo_parent
        if pdo.trans_type is None:
            return False
        return pdo.trans_type == 0 or (pdo.trans_type >= 254 and not pdo.event_timer)

    def synchronous_control(self):
        """Whether BaseNode402's control word goes in a synchronous RPDO (taken at a SYNC)."""
        pointer = self.node.rpdo_pointers.get(0x6040)
        if pointer is None:
            return False
        pdo = pointer.pdo_parent
        return pdo.trans_type is not None and pdo.trans_type <= 240

    def homing(self):
        """BaseNode402.homing(), or the CiA 402 homing handshake with the status word read by SDO
        where homing() cannot tell the answer to its start:
        - the status word comes only on a change: homing() takes a TPDO it has received twice for
          a periodic one and, after the start and at every check, waits 0.2 s for the next, which a
          drive sending on change only never sends once homing is attained;
        - the control word goes in a synchronous RPDO: homing() takes the second status word after
          its start for the answer, and with the RPDO sent on its own cycle and taken at a SYNC, the
          start may reach the drive after that status word was sampled, which then says "not
          started" (0x0400) and homing() reads INTERRUPTED."""
        node = self.node
        if self.has(0x6502) and not self.event_only_status() and not self.synchronous_control():
            check("homing() with method 35", node.homing(timeout=10), True)
            return
        self.set_mode("HOMING")
        check("op_mode", self.mode(), "HOMING")
        node.state = "OPERATION ENABLED"
        node.controlword = 0x000F
        node.controlword = 0x001F  # homing operation start (bit 4)
        wait_for("homing attained and target reached (status 0x1400 of 0x3400)",
                 lambda: self.statusword() & 0x3400 == 0x1400, 10)
        node.controlword = 0x000F

    def quick_stop(self):
        """Quick stop (control word 0x0002) from OPERATION ENABLED: the drive stops and, as its quick
        stop option code 0x605A says, stays in QUICK STOP ACTIVE (5-8) or goes on to SWITCH ON
        DISABLED (0-4); then SWITCH ON DISABLED."""
        node = self.node
        option = node.sdo[0x605A].raw if self.has(0x605A) else None
        stays = option is not None and 5 <= option <= 8
        want = "QUICK STOP ACTIVE" if stays else "SWITCH ON DISABLED"
        node.controlword = 0x0002
        wait_for(f"quick stop (0x605A = {option}) ends in {want}",
                 lambda: node.state == want and self.state_by_sdo() == want, 5)
        node.state = "SWITCH ON DISABLED"
        check("state", node.state, "SWITCH ON DISABLED")

    def state_by_sdo(self):
        sw = self.statusword()
        for state, (mask, bits) in self.node_state_masks():
            if sw & mask == bits:
                return state
        return f"UNKNOWN (0x{sw:04X})"

    @staticmethod
    def node_state_masks():
        from canopen.profiles.p402 import State402
        return State402.SW_MASK.items()

    MODES = {"PROFILED POSITION": (1, 0x01), "PROFILED VELOCITY": (3, 0x04), "HOMING": (6, 0x20),
             "CYCLIC SYNCHRONOUS POSITION": (8, 0x80)}

    def probe_modes(self):
        """The modes the drive takes by 0x6060 (read back in 0x6061), as 0x6502 bits."""
        from canopen.sdo.exceptions import SdoAbortedError
        bits = 0
        if not self.has(0x6060):
            skip("modes of operation", "the description has no 0x6060: a master can choose none")
            return 0
        for name, (code, bit) in self.MODES.items():
            try:
                self.node.sdo[0x6060].raw = code
            except SdoAbortedError as e:
                skip(name, f"the drive refuses 0x6060 = {code} ({e})")
                continue
            if self.node.sdo[0x6061].raw == code:
                ok(f"the drive takes 0x6060 = {code} ({name})")
                bits |= bit
        return bits

    def set_mode(self, mode):
        """node.op_mode = mode, or without 0x6502 in the description, 0x6060 written as put()
        writes and 0x6061 read by SDO."""
        if self.has(0x6502):
            self.node.op_mode = mode
            return
        code = self.MODES[mode][0]
        self.put(0x6060, code)
        wait_for(f"0x6061 = {code}", lambda: self.node.sdo[0x6061].raw == code, 2)

    def enter(self, mode):
        node = self.node
        self.set_mode(mode)
        check("op_mode", self.mode(), mode)
        # An RPDO that carries 0x6060 may carry a control word too: the drive may have left
        # OPERATION ENABLED on the way, as BaseNode402's homing() also assumes.
        node.state = "OPERATION ENABLED"
        node.controlword = 0x000F

    def read(self, index):
        return self.node.sdo[index].raw if self.has(index) else None

    def speed_limit(self):
        """The drive's max profile velocity 0x607F (counts/s), None without one."""
        return self.read(0x607F) or None

    def pp(self):
        """A move the drive's own limits let end within 2 s (as a user sizes a first move): +2,000
        counts at 10,000 counts/s, or less where 0x607F, 0x6083 or 0x6084 are lower."""
        node = self.node
        self.enter("PROFILED POSITION")
        v = 10000
        if self.has(0x6081):
            self.put(0x6081, v)
        v = min(v, self.speed_limit() or v)
        a = min(x for x in (self.read(0x6083), self.read(0x6084), 10 ** 9) if x)
        # Accelerating for at most 0.5 s and cruising for at most 1 s: d = v·t_cruise + v²/a.
        v = min(v, a // 2) or 1
        distance = max(1, min(2000, v + v * v // a))
        ok(f"pp: a move of {distance} counts at up to {v} counts/s, {a} counts/s²")
        target = self.position() + distance
        self.put(0x607A, target)
        time.sleep(2 * self.cycle)
        node.controlword = 0x001F  # new set-point (bit 4)
        wait_for("set-point acknowledged (status bit 12)",
                 lambda: self.statusword() & 0x1000, 2)
        node.controlword = 0x000F
        wait_for("target reached (status bit 10)",
                 lambda: self.statusword() & 0x1400 == 0x0400, 5)
        self.check_position("pp: position actual 0x6064 at target reached", target)

    def pv(self):
        self.enter("PROFILED VELOCITY")
        window = self.node.sdo[0x606D].raw if self.has(0x606D) else 0
        # 2,000 counts/s, or what the drive reaches in 0.5 s where 0x607F or 0x6083 are lower.
        a = self.read(0x6083) or 10 ** 9
        target = max(1, min(2000, self.speed_limit() or 2000, a // 2))
        self.put(0x60FF, target)
        wait_for(f"pv: velocity {target} counts/s reached (status bit 10)",
                 lambda: self.statusword() & 0x0400, 5)
        v = self.node.sdo[0x606C].raw
        if self.has(0x606D) and abs(v - target) > window:
            fail(f"pv: velocity actual 0x606C = {v}, not within 0x606D = {window} of {target}")
        ok(f"pv: velocity actual 0x606C = {v} at velocity reached")
        wait_for(f"pv: velocity actual 0x606C exactly {target} once the ramp has ended",
                 lambda: self.node.sdo[0x606C].raw == target, 2)
        self.put(0x60FF, 0)
        wait_for("pv: standstill (status bit 10 with target 0)",
                 lambda: self.statusword() & 0x0400 and abs(self.node.sdo[0x606C].raw) <= window,
                 5)

    def csp(self):
        self.start_sync()
        self.enter("CYCLIC SYNCHRONOUS POSITION")
        start = self.position()
        self.put(0x607A, start)
        time.sleep(3 * self.cycle)
        # Steps of 20 counts a cycle (2,000 counts/s), or less where 0x607F is lower.
        step = max(1, min(20, int((self.speed_limit() or 2000) * self.cycle / 2)))
        ok(f"csp: 100 set-points of +{step} counts, one every {self.args.cycle_ms} ms")
        for k in range(1, 101):
            self.put(0x607A, start + step * k)
            time.sleep(self.cycle)
        time.sleep(1.0)
        sw = self.statusword()
        check("csp: statusword state after the ramp (& 0x6F)", sw & 0x6F, 0x27)
        self.check_position("csp: position actual 0x6064 standing at the last set-point",
                            start + 100 * step)

    def close(self):
        try:
            self.network.sync.stop()
            for pdo in self.node.rpdo.values():
                pdo.stop()
        except Exception:
            pass
        self.network.disconnect()


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--eds", required=True)
    ap.add_argument("--node-id", type=int, required=True)
    bus = ap.add_mutually_exclusive_group(required=True)
    bus.add_argument("--socketcand", help="HOST:PORT of a socketcand server")
    bus.add_argument("--socketcan", help="a SocketCAN interface (vcan0)")
    ap.add_argument("--cycle-ms", type=int, default=10)
    args = ap.parse_args()
    if os.environ.get("CANOPEN_LOG"):
        logging.basicConfig(level=os.environ["CANOPEN_LOG"])
    master = Master(args)
    try:
        master.run()
    except Failed as e:
        print(f"FAIL {e}", flush=True)
        sys.exit(1)
    except Exception as e:  # python-canopen's own errors: the master could not go on
        print(f"FAIL {type(e).__name__}: {e}", flush=True)
        sys.exit(1)
    finally:
        master.close()
    print("PASS", flush=True)


if __name__ == "__main__":
    main()
