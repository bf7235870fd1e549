//! A real EtherCAT master against `ethercat-node`: SOEM, through pysoem, runs
//! `tests/python/pysoem_drives.py` on the master's end of a veth pair while the emulator answers on
//! the other (see `testkit::link`): vendors' CiA 402 drives from the corpus beside the checkout and
//! the example devices, to Op with Distributed Clocks (SYNC0 1 ms), every drive axis enabled by its
//! controlword and moved in cyclic synchronous position mode, 0x6064 read back from the process data
//! and by SDO. The script checks every value it sees and exits non-zero on the first mismatch; its
//! output and the emulator's log are shown when it does.
//!
//! Needs root (a network namespace, a veth pair, raw sockets), pysoem (`pip install pysoem`) and the
//! corpus: without any of them the tests fail and say why; they are never skipped.

use std::path::PathBuf;
use std::time::Instant;

#[path = "common/pysoem.rs"]
#[allow(dead_code)]
mod pysoem_master;

fn script() -> String {
    format!(
        "{}/tests/python/pysoem_drives.py",
        env!("CARGO_MANIFEST_DIR")
    )
}

/// A corpus file (from the workspace root, where the emulator runs), failing when it is missing.
fn corpus(name: &str) -> String {
    let rel = format!("../shared/corpus/esi/{name}");
    let path = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join(&rel);
    assert!(
        path.is_file(),
        "{} is missing: the tests read the vendors' ESIs from the corpus beside the checkout",
        path.display()
    );
    rel
}

/// `ethercat-node` with `node_args` on a fresh link, the script with `units` (its UNIT arguments)
/// and `extra`; the script's summary line.
fn run(node_args: &[&str], units: &[&str], extra: &[&str]) -> String {
    let started = Instant::now();
    let args: Vec<&str> = units.iter().chain(extra).copied().collect();
    let (stdout, answered) = pysoem_master::run_on(
        || testkit::link::Link::node(node_args),
        "ethercat-node",
        &script(),
        &args,
        std::time::Duration::from_secs(60),
    );
    let summary = stdout
        .lines()
        .last()
        .unwrap_or_else(|| panic!("no summary line\n{stdout}"))
        .to_string();
    println!(
        "{summary} [{:.2} s, {answered} frames answered]",
        started.elapsed().as_secs_f64()
    );
    summary
}

/// Four vendors' CiA 402 drives (Elmo, Ingenia, Copley with two axes in its default modules,
/// Synapticon), the example drive and the example I/O device in one chain: SOEM finds each by its
/// SII and 0x1018 (serial numbers 1 to 6), maps their process data as it reads their PDO
/// assignment by SDO (10 + 10, 11 + 11, 24 + 32, 13 + 13, 7 + 15 and 3 + 3 = 152 bytes), brings
/// them to Op with SYNC0 every 1 ms on the drives, and each of the 6 axes, enabled through Shutdown,
/// Switch on and Enable operation, ends its csp move exactly at its target (1,000 × its number,
/// every other one backwards).
#[test]
fn pysoem_moves_four_vendors_drives_and_the_examples_in_csp() {
    let (elmo, ingenia, copley, somanet) = (
        corpus("elmo-ECAT_00010420_V11.xml"),
        corpus("ingenia-eve-xcr-e.xml"),
        corpus("copley-XE2_4.60.xml"),
        corpus("somanet-CiA402-single.xml"),
    );
    let summary = run(
        &[
            "--esi",
            &elmo,
            "--device",
            "0x00030924",
            "--esi",
            &ingenia,
            "--esi",
            &copley,
            "--esi",
            &somanet,
            "--esi",
            "examples/drive.esi.xml",
            "--esi",
            "examples/io-device.esi.xml",
        ],
        &[
            "Elmo Drive,0x9a,0x30924,0",
            "EVE-XCR-E,0x29c,0x2c31001,0",
            "XE2,0xab,0x10b0,0+1",
            "CiA402 Motor Control Device,0x22d2,0x201,0",
            "drive,0xabc,0x402,0",
            "io-device,0xabc,0x191,-",
        ],
        &[],
    );
    assert!(summary.contains("6 units to Op"), "{summary}");
    assert!(summary.contains("6 axes enabled"), "{summary}");
    assert!(summary.contains("152 bytes of process data"), "{summary}");
}

/// The master configures the PDOs itself in Pre-Op (the example drive's configurable RxPDO 0x1603
/// assigned instead of 0x1600, TxPDO 0x1A01 remapped to statusword, position, mode display and
/// assigned instead of 0x1A00): SOEM then maps 2 + 4 + 4 + 1 = 11 and 2 + 4 + 1 = 7 bytes for that
/// unit, the other keeps 7 + 15, and both move.
#[test]
fn pysoem_configures_a_drives_pdos_itself() {
    let summary = run(
        &["--esi", "examples/drive.esi.xml@2"],
        &["drive,0xabc,0x402,0", "drive,0xabc,0x402,0"],
        &["--configure-pdos", "1"],
    );
    assert!(summary.contains("2 axes enabled"), "{summary}");
    assert!(summary.contains("40 bytes of process data"), "{summary}");
}

/// Modular devices with a given module list: the Copley XE2 with slot 1 empty and "Cyclic position
/// Mode" in slot 2 (axis B only: 12 + 16 bytes), and the ETG.2001 example with "Velocity Mode (DC)"
/// and "Position Mode (DC)" (12 + 12 bytes, no CiA 402 axis: its PDOs map 0x6041:01), to Op; axis B
/// moved.
#[test]
fn pysoem_runs_modular_devices_with_their_module_lists() {
    let (copley, etg) = (
        corpus("copley-XE2_4.60.xml"),
        corpus("etg2001-ModulesSlots_CiA402.xml"),
    );
    let summary = run(
        &[
            "--esi",
            &copley,
            "--modules",
            "none,0x10b00100",
            "--esi",
            &etg,
            "--modules",
            "0x0201,0x0101",
        ],
        &["XE2,0xab,0x10b0,1", "Drive1,0xe0000001,0x10000,-"],
        &[],
    );
    assert!(summary.contains("2 units to Op"), "{summary}");
    assert!(summary.contains("1 axes enabled"), "{summary}");
    assert!(summary.contains("52 bytes of process data"), "{summary}");
}

/// The case a real master failed on: each vendor's drive alone, a csp ramp of only 100 set-points
/// to +10,000 (100 counts a cycle from rest: more than these motors can follow at once), then
/// exactly one second standing at the last set-point: every axis stands exactly at +10,000 (and
/// Copley's axis B, the second axis, at −20,000).
#[test]
fn pysoem_ramps_100_set_points_and_every_axis_stands_exactly_at_its_target() {
    let cases = [
        (
            corpus("elmo-ECAT_00010420_V11.xml"),
            Some("0x00030924"),
            "Elmo Drive,0x9a,0x30924,0",
            "Elmo Drive axis 0: +0 → +10000",
        ),
        (
            corpus("ingenia-eve-xcr-e.xml"),
            None,
            "EVE-XCR-E,0x29c,0x2c31001,0",
            "EVE-XCR-E axis 0: +0 → +10000",
        ),
        (
            corpus("copley-XE2_4.60.xml"),
            None,
            "XE2,0xab,0x10b0,0+1",
            "XE2 axis 0: +0 → +10000; XE2 axis 1: +0 → -20000",
        ),
        (
            corpus("somanet-CiA402-single.xml"),
            None,
            "CiA402 Motor Control Device,0x22d2,0x201,0",
            "CiA402 Motor Control Device axis 0: +0 → +10000",
        ),
        (
            "examples/drive.esi.xml".to_string(),
            None,
            "drive,0xabc,0x402,0",
            "drive axis 0: +0 → +10000",
        ),
    ];
    for (esi, device, unit, moved) in cases {
        let mut node = vec!["--esi", esi.as_str()];
        if let Some(d) = device {
            node.extend(["--device", d]);
        }
        let summary = run(
            &node,
            &[unit],
            &[
                "--move",
                "10000",
                "--steps",
                "100",
                "--stand-cycles",
                "1000",
            ],
        );
        assert!(summary.contains(moved), "{summary}");
    }
}

/// A servo terminal whose drive profile is ETG.5001 MDP 742 (the test ESI after the EL7211's
/// layout): SOEM assigns the PDOs a configuration tool takes from the ESI for csp (0x1C12 = 0x1600
/// controlword, 0x1606 target position; 0x1C13 as at power-on: position, statusword, velocity),
/// sets mode 8 in 0x7010:03 by SDO, enables the channel by its controlword 0x7010:01 (the
/// statusword 0x6010:01 checked at each step), and ramps it in 100 set-points to +10,000: after one
/// second standing 0x6000:11 is exactly 10,000. 2 + 4 outputs and 4 + 2 + 4 inputs: 16 bytes.
#[test]
fn pysoem_moves_an_mdp742_servo_terminal_to_its_exact_target() {
    let summary = run(
        &["--esi", "ethercat-slave/tests/esi/mdp742-servo-1ch.xml"],
        &["EL7211-0010,0x2,0x1c2b3052,m0"],
        &[
            "--assign",
            "0:0x1600,0x1606:=",
            "--move",
            "10000",
            "--steps",
            "100",
            "--stand-cycles",
            "1000",
        ],
    );
    assert!(summary.contains("1 axes enabled"), "{summary}");
    assert!(
        summary.contains("EL7211-0010 channel m0: +0 → +10000"),
        "{summary}"
    );
    assert!(summary.contains("16 bytes of process data"), "{summary}");
}

/// A two-channel stepper terminal (the test ESI after the EL7062's layout, channel 2 at 0x7110,
/// 0x6110, 0x6100) with stepper motors: both channels in csp from power-on, ramped in 100
/// set-points to +10,000 and −20,000, and after one second standing exactly there. 2 × (2 + 4)
/// outputs and 2 × (4 + 2 + 4) inputs: 32 bytes.
#[test]
fn pysoem_moves_both_channels_of_an_mdp742_stepper_terminal() {
    let summary = run(
        &[
            "--esi",
            "ethercat-slave/tests/esi/mdp742-stepper-2ch.xml",
            "--motor",
            "stepper",
        ],
        &["EL7062,0x2,0x1b963052,m0+m1"],
        &[
            "--move",
            "10000",
            "--steps",
            "100",
            "--stand-cycles",
            "1000",
        ],
    );
    assert!(summary.contains("2 axes enabled"), "{summary}");
    assert!(
        summary.contains("EL7062 channel m0: +0 → +10000; EL7062 channel m1: +0 → -20000"),
        "{summary}"
    );
    assert!(summary.contains("32 bytes of process data"), "{summary}");
}
