//! `sdo-tool --ethercat IFACE` (this project's commissioning tool, an ethercrab master) against
//! `ethercat-node` on a veth pair: three vendors' CiA 402 drives from the corpus beside the
//! checkout and the example drive, their dictionaries listed by SDO Information and read without
//! `--od` (each entry's type from the slave's own description).

use std::path::PathBuf;
use std::process::Output;

use testkit::link::Link;

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

fn tool(link: &Link, argv: &[&str]) -> Output {
    link.sdo_tool(argv)
}

fn ok(link: &Link, argv: &[&str]) -> String {
    let o = tool(link, argv);
    assert!(
        o.status.success(),
        "sdo-tool {argv:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// `slaves --verbose`: the chain's identities from the SII (serial numbers by position); `sdos`: each slave's
/// dictionary by SDO Information (the example drive's 61 ESI objects and its drive simulation record
/// 0x5FF0, the PDO assignment written only in Pre-Op: `rwr-r-`); `read` without TYPE or --od: the
/// position actual of every axis (Copley's axis B at 0x6864), a statusword in Switch on disabled
/// (0x0260: bits 5, 6, 9), a string, the vendor ID of 0x1018 as the SII has it.
#[test]
fn sdo_tool_reads_the_drives_dictionaries_without_their_esis() {
    let (elmo, ingenia, copley) = (
        corpus("elmo-ECAT_00010420_V11.xml"),
        corpus("ingenia-eve-xcr-e.xml"),
        corpus("copley-XE2_4.60.xml"),
    );
    let link = Link::node(&[
        "--esi",
        &elmo,
        "--device",
        "0x00030924",
        "--esi",
        &ingenia,
        "--esi",
        &copley,
        "--esi",
        "examples/drive.esi.xml",
    ]);
    // IgH's --verbose blocks: each slave's state and SII identity (hex as IgH writes it).
    let slaves = ok(&link, &["slaves", "--verbose"]);
    let ids: Vec<Vec<&str>> = slaves
        .split("=== Slave ")
        .skip(1)
        .map(|block| {
            let value = |key: &str| {
                block
                    .lines()
                    .find_map(|l| l.trim_start().strip_prefix(key))
                    .map_or("", str::trim)
            };
            let position = block.split(' ').next().unwrap_or_default();
            vec![
                position,
                value("State:"),
                value("Vendor Id:"),
                value("Product code:"),
                value("Revision number:"),
                value("Serial number:"),
            ]
        })
        .collect();
    assert_eq!(
        ids,
        [
            [
                "1",
                "INIT",
                "0x0000009a",
                "0x00030924",
                "0x00010420",
                "0x00000001"
            ],
            [
                "2",
                "INIT",
                "0x0000029c",
                "0x02c31001",
                "0x00050014",
                "0x00000002"
            ],
            [
                "3",
                "INIT",
                "0x000000ab",
                "0x000010b0",
                "0x00010004",
                "0x00000003"
            ],
            [
                "4",
                "INIT",
                "0x00000abc",
                "0x00000402",
                "0x00010001",
                "0x00000004"
            ],
        ],
        "{slaves}"
    );
    let listing = ok(&link, &["sdos", "4"]);
    assert_eq!(
        listing.lines().filter(|l| l.starts_with("SDO ")).count(),
        62,
        "{listing}"
    );
    assert!(
        listing.contains(concat!(
            "SDO 0x1C12, RECORD, \"RxPDO assign\"\n",
            "  0x1C12:00, rwr-r-, UNSIGNED8, 8 bit, \"Number of assigned PDOs\"\n",
            "  0x1C12:01, rwr-r-, UNSIGNED16, 16 bit, \"PDO 1\"\n",
        )),
        "{listing}"
    );
    assert!(
        listing.contains("SDO 0x5FF0, RECORD, \"Drive simulation axis 1\"\n"),
        "{listing}"
    );
    assert!(
        listing.contains("  0x6064:00, r-r-r-, INTEGER32, 32 bit, \"Position actual value\"\n"),
        "{listing}"
    );
    for (node, object, value) in [
        ("1", "0x6064", "0"),
        ("2", "0x6064", "0"),
        ("3", "0x6064", "0"),
        ("3", "0x6864", "0"),
        ("4", "0x6064", "0"),
        // A statusword and the identity in hex with their width (SDO Information gives the type).
        ("2", "0x6041", "0x0260"),
        ("4", "0x1008", "\"drive\""),
        ("1", "0x1018:01", "0x0000009A"),
        ("3", "0x1018:04", "0x00000003"),
    ] {
        assert_eq!(
            ok(&link, &["read", node, object]),
            format!("{value}\n"),
            "read {node} {object}"
        );
    }
}
