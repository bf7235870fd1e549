//! A real EtherCAT master's session captured by the emulator (`ethercat-node --capture`) and read
//! by Wireshark's dissectors (tshark, `testkit::tshark`): SOEM, through pysoem, finds two example
//! drives, reads their identity by SDO and their dictionary by SDO Information in Pre-Op, maps and
//! runs them in Op with Distributed Clocks and moves both in csp
//! (`tests/python/pysoem_drives.py --sdo-info`). Every frame of the capture is EtherCAT to
//! Wireshark (`ecat`, the CoE mailboxes `ecat_mailbox`), none malformed, no expert error; each
//! frame received is answered by one sent; the SDO uploads, SDO Information's six services and
//! the AL control writes up to Op (8) are there.
//!
//! Needs root, pysoem and tshark (`scripts/setup-test-deps`).

use std::time::Duration;

use testkit::tshark;

#[path = "common/pysoem.rs"]
#[allow(dead_code)]
mod pysoem_master;

/// A number as tshark prints it: `0x…` hexadecimal, else decimal.
fn number(text: &str) -> u64 {
    match text.strip_prefix("0x") {
        Some(hex) => u64::from_str_radix(hex, 16).unwrap(),
        None => text.parse().unwrap(),
    }
}

#[test]
fn a_pysoem_session_captured_by_ethercat_node_reads_clean_in_wireshark() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("node.pcapng");
    let capture = file.to_str().unwrap().to_string();
    let script = format!(
        "{}/tests/python/pysoem_drives.py",
        env!("CARGO_MANIFEST_DIR")
    );
    let (summary, answered) = pysoem_master::run_on(
        || testkit::link::Link::node(&["--esi", "examples/drive.esi.xml@2", "--capture", &capture]),
        "ethercat-node",
        &script,
        &[
            "drive,0xabc,0x402,0",
            "drive,0xabc,0x402,0",
            "--steps",
            "50",
            "--sdo-info",
        ],
        Duration::from_secs(60),
    );
    assert!(summary.contains("2 axes enabled"), "{summary}");
    tshark::clean(&file, &[]);
    let rows = tshark::fields(
        &file,
        &[],
        &[
            "frame.packet_flags_direction",
            "ecat_mailbox.coe.sdoidx",
            "ecat_mailbox.coe.sdoinfoopcode",
            "ecat_mailbox.coe.sdoinfoindex",
            "ecat.reg.alctrl",
        ],
    );
    // Every frame answered, and each answer captured as sent.
    let inbound = rows.iter().filter(|r| number(&r[1]) == 1).count();
    let outbound = rows.iter().filter(|r| number(&r[1]) == 2).count();
    assert_eq!((inbound as u64, outbound as u64), (answered, answered));
    for r in &rows {
        assert!(r[0].starts_with("eth:ethertype:ecatf:ecat"), "{r:?}");
    }
    let all = |k: usize| -> Vec<u64> {
        rows.iter()
            .flat_map(|r| {
                r[k].split(',')
                    .filter(|v| !v.is_empty())
                    .map(number)
                    .collect::<Vec<_>>()
            })
            .collect()
    };
    assert!(rows.iter().any(|r| r[0].ends_with(":ecat_mailbox")));
    assert!(all(2).contains(&0x1018), "SDO uploads of 0x1018");
    let opcodes = all(3);
    for op in 1..=6 {
        assert!(opcodes.contains(&op), "SDO Information opcode {op}");
    }
    assert!(all(4).contains(&0x6040) && all(4).contains(&0x6041));
    // AL control (0x0120) written with Pre-Op (2), Safe-Op (4) and Op (8) by the master.
    let states: Vec<u64> = all(5).iter().map(|c| c & 0x0F).collect();
    for state in [2, 4, 8] {
        assert!(states.contains(&state), "AL control {state} in {states:?}");
    }
}
