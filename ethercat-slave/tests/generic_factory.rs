//! What an `ethercat-node` unit reports where its ESI leaves values out, in process: 0x1018 the
//! identity its SII carries (Ingenia's ESI object says another product code), a drive's device
//! type (Copley's two axes), supported modes (Elmo) and factory settings, each said once per kind
//! of device; read by SDO through the unit's mailbox and accepted when written back. Then every
//! drive of every ESI of the corpus: each value of its profile area that it reports, it takes back.

#[path = "common/node.rs"]
mod node;

use std::time::{Duration, Instant};

use ds402::drive::{DriveConfig, MotorKind};
use ethercat_slave::generic::{self, Template};
use ethercat_slave::master::Layout;
use ethercat_slave::unit::Model;
use node::*;
use od::hook::Bound;
use od::sdo::store::ObjectStore;
use od::Address;

/// The process values a drive computes (`ds402::drive`): read-only.
const PROCESS: [u16; 13] = [
    0x603F, 0x6041, 0x6061, 0x6062, 0x6063, 0x6064, 0x606B, 0x606C, 0x6074, 0x6077, 0x60F4, 0x60FC,
    0x60FD,
];

fn lines(t: &Template) -> Vec<String> {
    t.events().iter().map(|e| e.line()).collect()
}

/// Ingenia's EVE-XCR-E: its 0x1018 object gives product code 0x32 and revision 0, its `Type`
/// 0x02C31001 and 327700 (0x00050014), which the SII carries: the unit reports the SII's; its ESI
/// gives 0x605D, 0x6081, 0x6083, 0x6084 and 0x6099 as 0: the drive's values instead. By SDO in
/// Pre-Op: the exact bytes, each accepted when written back.
#[test]
fn ingenia_reports_its_sii_identity_and_factory_settings() {
    let t = template(&corpus("ingenia-eve-xcr-e.xml"), None);
    assert_eq!(
        lines(&t),
        [
            "0x1018:02 product code = 0x02C31001 (the ESI's object gives 0x00000032, its Type \
             0x02C31001, which the SII carries and a master compares with 0x1018)",
            "0x1018:03 revision number = 0x00050014 (the ESI's object gives 0x00000000, its Type \
             0x00050014, which the SII carries and a master compares with 0x1018)",
            "0x605D halt option code = 1 (the description gives 0, a code outside 1 to 4, which it \
             refuses: its default)",
            "0x6081 profile velocity = 10000 counts/s (the description gives 0, which would stop \
             every profile position move: a factory default)",
            "0x6083 profile acceleration = 100000 counts/s² (the description gives 0, which would \
             stop every move: a factory default)",
            "0x6084 profile deceleration = 100000 counts/s² (the description gives 0, which would \
             stop every move: a factory default)",
            "0x6099:01 homing speed during search for switch = 5000 counts/s (the description \
             gives 0, which would never find home: a factory default)",
            "0x6099:02 homing speed during search for zero = 1000 counts/s (the description gives \
             0, which would never find home: a factory default)",
        ]
    );
    let layout = Layout::of(&t);
    let mut c = chain(&[(&t, 1)]);
    configure(&mut c, std::slice::from_ref(&layout));
    request(&mut c, 0x02);
    c.cycle(Duration::from_millis(1));
    for (index, sub, bytes) in [
        (0x1018u16, 2u8, vec![0x01, 0x10, 0xC3, 0x02]),
        (0x1018, 3, vec![0x14, 0x00, 0x05, 0x00]),
        (0x605D, 0, vec![0x01, 0x00]),
        (0x6083, 0, vec![0xA0, 0x86, 0x01, 0x00]),
        (0x6099, 2, vec![0xE8, 0x03, 0x00, 0x00]),
    ] {
        assert_eq!(
            upload(&mut c, &layout, 0, index, sub),
            Ok(bytes.clone()),
            "{index:04X}:{sub:02X}"
        );
        if index != 0x1018 {
            assert_eq!(
                download(&mut c, &layout, 0, index, sub, &bytes),
                Ok(()),
                "{index:04X}:{sub:02X} written back"
            );
        }
    }
}

/// Copley's XE2 with its two axes in its default modules: 0x1000 without a value reads 0xFFFF0192
/// (several logical devices of CiA 402), its names its `Type` and revision number; a stepper
/// template says so in the events.
#[test]
fn copley_reports_a_device_of_two_axes() {
    let path = corpus("copley-XE2_4.60.xml");
    let t = template(&path, None);
    assert_eq!(t.axes(), [0, 1]);
    assert_eq!(
        lines(&t)[..3],
        [
            "0x1000 device type = 0xFFFF0192 (the description gives no value: a CiA 402 servo \
             drive of 2 axes (0xFFFF: several logical devices, each describing itself at 0x67FF + \
             0x800 · axis))",
            "0x1008 manufacturer device name = \"XE2\" (the description gives no value: its Type)",
            "0x100A manufacturer software version = \"0x00010004\" (the description gives no \
             value: its revision number)",
        ]
    );
    let layout = Layout::of(&t);
    let mut c = chain(&[(&t, 1)]);
    configure(&mut c, std::slice::from_ref(&layout));
    request(&mut c, 0x02);
    c.cycle(Duration::from_millis(1));
    assert_eq!(
        upload(&mut c, &layout, 0, 0x1000, 0),
        Ok(vec![0x92, 0x01, 0xFF, 0xFF])
    );
    assert_eq!(upload(&mut c, &layout, 0, 0x1008, 0), Ok(b"XE2".to_vec()));
    let spec = ethercat_slave::node_cli::EsiSpec {
        path,
        units: None,
        device: None,
        modules: None,
    };
    let mut config = DriveConfig::default();
    config.motor.kind = MotorKind::Stepper;
    let stepper = ethercat_slave::node_cli::load_for(&spec, &config).unwrap();
    assert!(lines(&stepper)[0].contains("a CiA 402 stepper motor drive of 2 axes"));
}

/// Elmo's drive (product 0x00030924, revision 1): its ESI gives 0x1018 and 0x6502 no values: the
/// identity of its `Type` and the modes it runs whose objects it has (pp, pv, hm, csp, csv, cst:
/// 0x3A5, the cyclic ones on SYNC0).
#[test]
fn elmo_reports_its_identity_and_the_modes_it_runs() {
    let t = template(&corpus("elmo-ECAT_00010420_V11.xml"), Some("0x00030924"));
    let l = lines(&t);
    assert_eq!(
        l[0],
        "0x1018:01 vendor-ID = 0x0000009A (the description gives no value: its identity's \
         vendor-ID)"
    );
    assert_eq!(
        l.last().unwrap(),
        "0x6502 supported drive modes = 0x000003A5 (the description gives no value: the modes \
         this drive runs whose objects it has)"
    );
    let layout = Layout::of(&t);
    let mut c = chain(&[(&t, 1)]);
    configure(&mut c, std::slice::from_ref(&layout));
    request(&mut c, 0x02);
    c.cycle(Duration::from_millis(1));
    assert_eq!(read(&mut c, &layout, 0, 0x6502, 0), 0x3A5);
    assert_eq!(read(&mut c, &layout, 0, 0x1018, 1), 0x9A);
    assert_eq!(read(&mut c, &layout, 0, 0x1018, 2), 0x0003_0924);
}

/// Every device with drive axes of every ESI of the corpus, its unit in Pre-Op: each readable and
/// writable entry of the profile area (0x6000–0x9FFF) that Pre-Op may write, read as the unit
/// reports it and written back as read, is accepted.
#[test]
fn every_corpus_drive_unit_takes_back_what_it_reports() {
    let dir = root().join("../shared/corpus/esi");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e} (the corpus beside the checkout)", dir.display()))
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    let mut drives = 0;
    for path in files {
        let bytes = std::fs::read(&path).unwrap();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        let Ok(devices) = od::esi::read_all(&bytes, &name) else {
            continue;
        };
        for desc in devices {
            let device = format!("{name} {}", generic::device_name(&desc));
            let Ok(t) = Template::new(desc, None) else {
                continue;
            };
            if t.axes().is_empty() {
                continue;
            }
            drives += 1;
            let now = Instant::now();
            let mut c = generic::chain(
                &[(&t, 1)],
                &DriveConfig::default(),
                Duration::from_millis(1),
                now,
            )
            .unwrap();
            let unit = c.unit_mut(0).unwrap();
            unit.set_al_state(
                ethercat_slave::esc::al::AlState::Init,
                ethercat_slave::esc::al::AlState::PreOp,
                now,
            );
            let entries: Vec<Address> = unit
                .dict()
                .objects()
                .filter(|o| (0x6000..=0x9FFF).contains(&o.index))
                .flat_map(|o| {
                    o.subs
                        .iter()
                        .filter(|(_, s)| {
                            s.access.kind.readable()
                                && s.access.kind.writable()
                                && s.data_type != od::DataType::Domain
                                && s.access
                                    .write_states
                                    .is_none_or(|w| w.contains(od::EcatStates::PREOP))
                        })
                        .map(|(&sub, _)| Address::new(o.index, sub))
                        .collect::<Vec<_>>()
                })
                .collect();
            let (dict, hook) = od::hook::Objects::split(unit);
            let mut node = Bound::new(dict, hook, std::time::Instant::now());
            for at in entries {
                let Ok(bytes) = node.upload(at) else {
                    continue;
                };
                // What the drive measures is read-only whatever the ESI says (Copley's 0x6063 is
                // `rw`): refused as such (0x06010002), which a master skips (`sdo-tool apply`).
                let standard = 0x6000 + (at.index - 0x6000) % 0x800;
                if PROCESS.contains(&standard) {
                    assert_eq!(node.download(at, &bytes), Err(od::AbortCode::ReadOnly));
                    continue;
                }
                assert_eq!(
                    node.download(at, &bytes),
                    Ok(()),
                    "{device}: {at} = {bytes:02X?} refused written back"
                );
            }
        }
    }
    // Elmo's, Ingenia's, Copley's, Synapticon's drives and more.
    assert!(drives >= 10, "only {drives} drives");
}
