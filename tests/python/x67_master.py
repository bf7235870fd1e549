"""python-canopen as the master of the virtual X67 node.

Usage: x67_master.py --eds EDS --node-id N (--socketcand HOST:PORT | --socketcan IFACE)

Reads the identity and the device name (segmented and block upload), writes and reads back
configuration registers, switches NMT states (seen in the heartbeat), reads the PDO maps from the
node, receives TPDOs and sends RPDOs, brings axis 1 through the Ramp state machine to Operation
enabled and moves it to a target in mode 1. Prints one line per step; exits 1 at the first
difference, naming what was expected and what came.
"""

import argparse
import sys
import threading
import time

import canopen


def check(what, got, want):
    if got != want:
        print(f"FAIL {what}: expected {want!r}, got {got!r}", flush=True)
        sys.exit(1)
    print(f"ok   {what}: {got!r}", flush=True)


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


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--eds", required=True)
    ap.add_argument("--node-id", type=int, required=True)
    ap.add_argument("--socketcand")
    ap.add_argument("--socketcan")
    args = ap.parse_args()

    network = canopen.Network()
    if args.socketcand:
        host, port = args.socketcand.rsplit(":", 1)
        network.connect(interface="socketcand", host=host, port=int(port), channel="can0")
    else:
        network.connect(interface="socketcan", channel=args.socketcan)
    try:
        run(network, args)
    finally:
        network.disconnect()
    print("PASS", flush=True)


def run(network, args):
    node = canopen.RemoteNode(args.node_id, args.eds)
    network.add_node(node)
    # Generous bounds: the node answers within milliseconds, but the machine may be busy.
    node.sdo.RESPONSE_TIMEOUT = 5.0

    # Reset the node and see it boot: listen before asking, so that a boot-up message that comes back
    # before this thread waits is not missed.
    booted = threading.Event()

    def on_heartbeat(can_id, data, timestamp):
        if bytes(data) == b"\x00":
            booted.set()

    network.subscribe(0x700 + args.node_id, on_heartbeat)
    node.nmt.send_command(0x81)
    if not booted.wait(15):
        print("FAIL boot-up after reset node: not within 15 s", flush=True)
        sys.exit(1)
    network.unsubscribe(0x700 + args.node_id, on_heartbeat)
    print("ok   boot-up after reset node", flush=True)

    # Identity and strings.
    check("1000 device type", node.sdo[0x1000].raw, 0)
    check("1018:00", node.sdo[0x1018][0].raw, 4)
    name = node.sdo[0x1008].raw
    check("1008 device name (segmented upload)", name, "X67BC4321-10 / X67SM2436")
    with node.sdo.open(0x1008, 0, "rb", block_transfer=True) as f:
        data = f.read()
    check("1008 device name (block upload)", data, b"X67BC4321-10 / X67SM2436")

    # Configuration registers: written, then read back through their read-back registers.
    node.sdo["ConfigOutput03a"].raw = 20
    node.sdo["ConfigOutput04a"].raw = 50
    node.sdo["ConfigOutput05a"].raw = 100
    check("ConfigOutput03aRead", node.sdo["ConfigOutput03aRead"].raw, 20)
    check("ConfigOutput04aRead", node.sdo["ConfigOutput04aRead"].raw, 50)
    check("ConfigOutput05aRead", node.sdo["ConfigOutput05aRead"].raw, 100)
    node.sdo["MaxSpeed01pos"].raw = 100
    node.sdo["MaxAcc01"].raw = 10
    node.sdo["MaxDec01"].raw = 10
    try:
        node.sdo["ConfigOutput03a"].raw = 168
        print("FAIL ConfigOutput03a = 168 was accepted", flush=True)
        sys.exit(1)
    except canopen.SdoAbortedError as e:
        check("ConfigOutput03a = 168 refused", e.code, 0x06090031)
    node.sdo[0x1017].raw = 100
    check("1017 heartbeat time", node.sdo[0x1017].raw, 100)

    # NMT states as the heartbeat reports them.
    for command, state in [
        ("OPERATIONAL", "OPERATIONAL"),
        ("STOPPED", "STOPPED"),
        ("PRE-OPERATIONAL", "PRE-OPERATIONAL"),
    ]:
        node.nmt.state = command
        # The heartbeat (100 ms) reports the new state; a late thread may still see an older one.
        wait_for(f"NMT {command} in the heartbeat", lambda: node.nmt.state == state, 3)
        check(f"NMT {command}", node.nmt.state, state)

    # PDO maps as the node holds them.
    node.tpdo.read()
    node.rpdo.read()
    check(
        "TPDO 1 map",
        [v.name for v in node.tpdo[1].map],
        ["AbsPos01ActVal", "MpGenStatus01", "InputStatus", "Dummy0005"],
    )
    check(
        "RPDO 1 map",
        [v.name for v in node.rpdo[1].map],
        ["AbsPos01", "MpGenControl01", "MpGenMode01", "Dummy0005"],
    )
    node.nmt.state = "OPERATIONAL"
    node.tpdo[1].wait_for_reception(6)
    print("ok   TPDO 1 received", flush=True)

    def status():
        return node.tpdo[1]["MpGenStatus01"].raw

    def send(position, control, mode):
        node.rpdo[1]["AbsPos01"].raw = position
        node.rpdo[1]["MpGenControl01"].raw = control
        node.rpdo[1]["MpGenMode01"].raw = mode
        node.rpdo[1].transmit()

    # The Ramp state machine: Switch on disabled -> Ready to switch on -> Switched on -> Operation enabled.
    wait_for("Switch on disabled", lambda: status() & 0x004F == 0x0040, 9)
    send(0, 0x0006, 1)
    wait_for("Ready to switch on", lambda: status() & 0x006F == 0x0021, 6)
    send(0, 0x0007, 1)
    wait_for("Switched on", lambda: status() & 0x006F == 0x0023, 9)
    send(0, 0x000F, 1)
    wait_for("Operation enabled", lambda: status() & 0x006F == 0x0027, 6)

    # Mode 1: move to 5000 and see the target reached at exactly that position.
    send(5000, 0x000F, 1)
    wait_for(
        "target 5000 reached (status bit 10)",
        lambda: node.tpdo[1]["AbsPos01ActVal"].raw == 5000 and status() & 0x0400,
        30,
    )
    check("AbsPos01ActVal by TPDO", node.tpdo[1]["AbsPos01ActVal"].raw, 5000)
    check("AbsPos01ActVal by SDO", node.sdo["AbsPos01ActVal"].raw, 5000)

    # Digital input 1 from the simulation object (not in the EDS: a raw download) shows in InputStatus.
    node.sdo.download(0x5F00, 1, b"\x01")
    wait_for("DI1 in InputStatus", lambda: node.tpdo[1]["InputStatus"].raw == 0x01, 6)


if __name__ == "__main__":
    main()
