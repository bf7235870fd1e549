"""python-canopen as the master of `canopen-node`.

Usage:
  canopen_master.py drive402 --eds EDS --node-id N BUS   a CiA 402 drive through BaseNode402
  canopen_master.py lss --eds EDS --assign N BUS         Fastscan, configure, store, boot-up
  canopen_master.py block --eds EDS --node-id N BUS      block download and upload of a DOMAIN
BUS: --socketcand HOST:PORT or --socketcan IFACE.

drive402 runs what the drive's 0x6502 supports, in this order: the state machine to OPERATION
ENABLED by `node.state = ...`, homing by `node.homing()` (method 35: the current position is home),
a profile-position move by the set-point handshake, a profile-velocity run, a cyclic synchronous
position ramp on SYNC, and back to SWITCH ON DISABLED. Prints one line per step; exits 1 at the first
difference, naming what was expected and what came.
"""

import argparse
import logging
import os
import sys
import time

import canopen
from canopen.profiles.p402 import BaseNode402


def check(what, got, want):
    if got != want:
        print(f"FAIL {what}: expected {want!r}, got {got!r}", flush=True)
        sys.exit(1)
    print(f"ok   {what}: {got!r}", flush=True)


def near(what, got, want, tolerance):
    if abs(got - want) > tolerance:
        print(f"FAIL {what}: expected {want} ± {tolerance}, got {got}", flush=True)
        sys.exit(1)
    print(f"ok   {what}: {got} (want {want} ± {tolerance})", flush=True)


def wait_for(what, predicate, timeout):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        value = predicate()
        if value:
            print(f"ok   {what}", flush=True)
            return value
        time.sleep(0.01)
    print(f"FAIL {what}: not within {timeout} s", flush=True)
    sys.exit(1)


def connect(args):
    network = canopen.Network()
    if args.socketcand:
        host, port = args.socketcand.rsplit(":", 1)
        network.connect(interface="socketcand", host=host, port=int(port), channel="can0")
    else:
        network.connect(interface="socketcan", channel=args.socketcan)
    return network


def has(node, index):
    return index in node.object_dictionary


def put(node, index, value):
    """Writes a drive object: by SDO, unless RPDOs sent cyclically map it (they would write over it
    every cycle): then into each of them, which carry it with their next cycle. (An event-driven RPDO
    that maps it is not used: python-canopen would send that RPDO's own copy of any control word
    mapped beside it.)"""
    cyclic = [v for pdo in node.rpdo.values() if pdo.enabled and pdo.is_periodic
              for v in pdo if v.index == index]
    if not cyclic:
        node.sdo[index].raw = value
        return
    for v in cyclic:
        v.raw = value
    # Taken at a SYNC after the RPDO's next cycle: go on once the drive has it.
    wait_for(f"0x{index:04X} = {value} through its RPDO", lambda: node.sdo[index].raw == value, 2)


def drive402(args):
    network = connect(args)
    node = BaseNode402(args.node_id, args.eds)
    network.add_node(node)
    # Every answer of this drive comes within a few ms; python-canopen's own timeouts are the bounds.
    node.sdo.RESPONSE_TIMEOUT = 2.0
    node.nmt.state = "PRE-OPERATIONAL"
    node.setup_402_state_machine()
    # BaseNode402 waits for the next TPDO with the status word once it has seen two (it then takes
    # the PDO for periodic): the TPDOs of the drive's status go on SYNC, as a cyclic master has them.
    for tpdo in node.tpdo.values():
        if tpdo.enabled and any(v.index in (0x6041, 0x6061) for v in tpdo):
            tpdo.trans_type = 1
            tpdo.save()
            print(f"ok   TPDO 0x{tpdo.cob_id:03X} on every SYNC", flush=True)
    # The control word goes in an event-driven RPDO, so that each command reaches the drive at once
    # and the next status word answers it.
    for rpdo in node.rpdo.values():
        if rpdo.enabled and rpdo.trans_type is not None and rpdo.trans_type <= 240 and any(
            v.index == 0x6040 for v in rpdo
        ):
            rpdo.trans_type = 255
            rpdo.save()
            print(f"ok   RPDO 0x{rpdo.cob_id:03X} event-driven", flush=True)
    supported = node.sdo[0x6502].raw
    print(f"ok   supported drive modes 0x{supported:08X}", flush=True)
    # SYNC for TPDOs that go on SYNC, and for cyclic synchronous modes. BaseNode402.homing() takes
    # the first status word after its start command for the answer to it; one sampled at a SYNC
    # before the command reached the drive still says "not started" (0x0400, which it reads as
    # INTERRUPTED). A SYNC period long against the bus latency keeps that window small.
    network.sync.start(0.05)
    node.nmt.state = "OPERATIONAL"
    # RPDOs that take effect on SYNC are sent cyclically, as BaseNode402 expects of them.
    for rpdo in node.rpdo.values():
        if rpdo.enabled and rpdo.is_periodic:
            rpdo.start(0.05)
            print(f"ok   RPDO 0x{rpdo.cob_id:03X} sent every 50 ms", flush=True)
    time.sleep(0.1)

    node.state = "SWITCH ON DISABLED"
    check("state", node.state, "SWITCH ON DISABLED")
    node.state = "OPERATION ENABLED"
    check("state", node.state, "OPERATION ENABLED")
    check("statusword & 0x6F", node.sdo[0x6041].raw & 0x6F, 0x27)

    if supported & 0x20:
        if has(node, 0x6098):
            node.sdo[0x6098].raw = 35
        check("homing()", node.homing(timeout=10), True)
        offset = node.sdo[0x607C].raw if has(node, 0x607C) else 0
        near("position after homing on the current position", node.sdo[0x6064].raw, offset, 2)

    if supported & 0x01:
        node.op_mode = "PROFILED POSITION"
        check("op_mode", node.op_mode, "PROFILED POSITION")
        # An RPDO that carries 0x6060 carries a control word too (python-canopen sends its own copy,
        # 0 when never set): the drive may have left OPERATION ENABLED, as homing() also assumes.
        node.state = "OPERATION ENABLED"
        start = node.sdo[0x6064].raw
        target = start + 20000
        if has(node, 0x6081):
            put(node, 0x6081, 40000)
        if has(node, 0x6083):
            put(node, 0x6083, 400000)
        if has(node, 0x6084):
            put(node, 0x6084, 400000)
        put(node, 0x607A, target)
        node.controlword = 0x000F
        node.controlword = 0x001F  # new set-point (bit 4)
        wait_for("set-point acknowledged (status bit 12)",
                 lambda: node.sdo[0x6041].raw & 0x1000, 2)
        node.controlword = 0x000F
        wait_for("target reached (status bit 10)",
                 lambda: node.sdo[0x6041].raw & 0x0400 and not node.sdo[0x6041].raw & 0x1000, 10)
        near("position actual (0x6064) at the target", node.sdo[0x6064].raw, target, 20)

    if supported & 0x04:
        node.op_mode = "PROFILED VELOCITY"
        check("op_mode", node.op_mode, "PROFILED VELOCITY")
        node.state = "OPERATION ENABLED"
        node.controlword = 0x000F
        put(node, 0x60FF, 5000)
        wait_for("velocity reached (status bit 10)",
                 lambda: node.sdo[0x6041].raw & 0x0400 and abs(node.sdo[0x606C].raw - 5000) <= 100, 5)
        near("velocity actual (0x606C)", node.sdo[0x606C].raw, 5000, 100)
        put(node, 0x60FF, 0)
        wait_for("standstill (status bit 12, speed 0)",
                 lambda: node.sdo[0x6041].raw & 0x1000 and abs(node.sdo[0x606C].raw) <= 100, 5)

    if supported & 0x80:
        node.op_mode = "CYCLIC SYNCHRONOUS POSITION"
        check("op_mode", node.op_mode, "CYCLIC SYNCHRONOUS POSITION")
        node.state = "OPERATION ENABLED"
        node.controlword = 0x000F
        start = node.sdo[0x6064].raw
        for k in range(1, 51):
            put(node, 0x607A, start + 100 * k)
            time.sleep(0.01)
        target = start + 5000
        wait_for("csp: the position follows to the last target",
                 lambda: abs(node.sdo[0x6064].raw - target) <= 20, 5)
        near("position actual after the csp ramp", node.sdo[0x6064].raw, target, 20)

    node.state = "SWITCH ON DISABLED"
    check("state", node.state, "SWITCH ON DISABLED")
    network.sync.stop()
    network.disconnect()
    print("PASS", flush=True)


def lss(args):
    network = connect(args)
    # A slave that does not match stays silent: each such step waits this long.
    network.lss.RESPONSE_TIMEOUT = 0.2
    network.lss.send_switch_state_global(network.lss.WAITING_STATE)
    found, address = network.lss.fast_scan()
    check("fastscan found a node", found, True)
    od = canopen.import_od(args.eds)
    identity = od[0x1018]
    for sub, name in [(1, "vendor-ID"), (2, "product code"), (3, "revision number")]:
        check(f"fastscan {name}", address[sub - 1], int(identity[sub].default))
    print(f"ok   serial number 0x{address[3]:08X}", flush=True)
    check("inquire node-ID (none)", network.lss.inquire_node_id(), 0xFF)
    # The scan is over: every service from here on is answered. Store configuration is answered once
    # the node's storage has the node-ID (a write and its fsync): a slow or emulated disk takes longer
    # than a scan step, so the confirmed services get the time a slow disk needs.
    network.lss.RESPONSE_TIMEOUT = 2.0
    network.lss.configure_node_id(args.assign)
    network.lss.store_configuration()
    node = network.add_node(args.assign, args.eds)
    node.sdo.RESPONSE_TIMEOUT = 2.0
    bootups = []
    network.subscribe(0x700 + args.assign, lambda can_id, data, ts: bootups.append(bytes(data)))
    network.lss.send_switch_state_global(network.lss.WAITING_STATE)
    wait_for("boot-up of the node with its new node-ID", lambda: bootups, 5)
    check("boot-up message", bootups[0], b"\x00")
    check("EMCY COB-ID follows the node-ID", node.sdo[0x1014].raw, 0x80 + args.assign)
    network.disconnect()
    print("PASS", flush=True)


def block(args):
    network = connect(args)
    node = network.add_node(args.node_id, args.eds)
    node.sdo.RESPONSE_TIMEOUT = 2.0
    data = bytes((i * 37 + 11) % 256 for i in range(3000))
    with node.sdo.open(0x2000, 1, "wb", size=len(data), block_transfer=True) as f:
        f.write(data)
    print("ok   block download of 3000 bytes", flush=True)
    with node.sdo.open(0x2000, 1, "rb", block_transfer=True) as f:
        got = f.read()
    check("block upload gives them back", got == data, True)
    check("segmented upload of the same", node.sdo.upload(0x2000, 1) == data, True)
    network.disconnect()
    print("PASS", flush=True)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("what", choices=["drive402", "lss", "block"])
    ap.add_argument("--eds", required=True)
    ap.add_argument("--node-id", type=int)
    ap.add_argument("--assign", type=int)
    ap.add_argument("--socketcand")
    ap.add_argument("--socketcan")
    args = ap.parse_args()
    if os.environ.get("CANOPEN_LOG"):
        logging.basicConfig(level=os.environ["CANOPEN_LOG"])
    {"drive402": drive402, "lss": lss, "block": block}[args.what](args)


if __name__ == "__main__":
    main()
