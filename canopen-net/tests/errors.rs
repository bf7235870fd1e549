//! Every error a bus description can have, with its exact message: the file, the line, the key and
//! what is wrong.

use std::path::Path;

use canopen_net::{check, generate, Bus, GenOptions, SlaveFile};

fn load(dcf: &str) -> Result<SlaveFile, String> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/net")
        .join(dcf);
    let (_, reading) = od::load::load_reading(&path).map_err(|_| format!("cannot read {dcf}"))?;
    let text = std::fs::read(&path).unwrap();
    Ok(SlaveFile::new(
        reading.devices.into_iter().next().unwrap(),
        &text,
    ))
}

/// The error generating `yaml` gives.
fn error(yaml: &str) -> String {
    let bus = match Bus::parse(yaml, "bus.yml") {
        Ok(bus) => bus,
        Err(e) => return e.to_string(),
    };
    match generate(&bus, &mut load, &|_| None, GenOptions::default()) {
        Ok(_) => "no error".into(),
        Err(e) => e.to_string(),
    }
}

const HEAD: &str = "master: {node_id: 1}\ndrive:\n  dcf: ../../examples/drive.eds\n  node_id: 2\n";

#[test]
fn yaml_that_does_not_parse() {
    assert_eq!(
        error("master: {node_id: 1\n"),
        "bus.yml:2: while parsing a flow mapping, did not find expected ',' or '}'"
    );
    assert_eq!(
        error("- 1\n"),
        "bus.yml:1: the bus description is no mapping"
    );
    assert_eq!(
        error("drive: {dcf: a.eds}\n"),
        "bus.yml:1: master: there is no master section"
    );
}

#[test]
fn slave_sections() {
    assert_eq!(
        error("master: {}\nx:\n  node_id: 2\n"),
        "bus.yml:2: x: no dcf is given"
    );
    assert_eq!(
        error("master: {}\nx: {dcf: nope.eds}\n"),
        "bus.yml:2: x.dcf: cannot read nope.eds"
    );
    assert_eq!(error("master: {}\nx: 7\n"), "bus.yml:2: x: is no mapping");
    assert_eq!(
        error("master: {}\nx:\n  dcf: ../../examples/drive.eds\n"),
        "bus.yml:2: x: 0x1014/0 is given as $NODEID+…, and the slave has no node_id"
    );
    assert_eq!(
        error("master: {}\nx:\n  dcf: ../../examples/drive.eds\n  node_id: 300\n"),
        "bus.yml:4: x.node_id: 300 is out of range 0..255"
    );
    assert_eq!(
        error("master: {}\nx:\n  dcf: ../../examples/drive.eds\n  node_id: 2\n  heartbeat_producer: soon\n"),
        "bus.yml:5: x.heartbeat_producer: 'soon' is no integer"
    );
    assert_eq!(
        error("master: {node_id: -1}\n"),
        "bus.yml:1: master.node_id: -1 is out of range 0..4294967295"
    );
}

#[test]
fn a_description_the_strict_reading_refuses() {
    assert_eq!(
        error(
            "master: {}\nx:\n  dcf: ../../../shared/corpus/eds/cnrtt-project.eds\n  node_id: 3\n"
        ),
        "bus.yml:3: x.dcf: invalid DCF: ../../../shared/corpus/eds/cnrtt-project.eds \
         (invalid entry in [DeviceInfo]: NG_Slave; -S takes it as it is)"
    );
}

#[test]
fn entries_the_slave_cannot_take() {
    let e = |tail: &str| error(&format!("{HEAD}{tail}"));
    assert_eq!(
        e("  sdo:\n    - {index: 0x2FFF, value: 1}\n"),
        "bus.yml:6: drive.sdo: drive: object 0x2FFF does not exist"
    );
    assert_eq!(
        e("  sdo:\n    - {index: 0x1018, sub_index: 9}\n"),
        "bus.yml:6: drive.sdo: drive: sub-object 0x1018/9 does not exist"
    );
    assert_eq!(
        e("  sdo:\n    - {index: 0x6060, value: 300}\n"),
        "bus.yml:6: drive.sdo: drive: 300 is out of range for 0x6060/0"
    );
    assert_eq!(
        e("  sdo:\n    - {sub_index: 1}\n"),
        "bus.yml:6: drive.sdo: an entry without index"
    );
    assert_eq!(e("  sdo: 5\n"), "bus.yml:5: drive.sdo: is no list");
}

#[test]
fn pdos_the_slave_cannot_take() {
    let e = |tail: &str| error(&format!("{HEAD}{tail}"));
    assert_eq!(
        e("  tpdo:\n    9: {}\n"),
        "bus.yml:6: drive.tpdo: drive: Transmit-PDO 9 not available"
    );
    assert_eq!(
        e("  rpdo:\n    5: {}\n"),
        "bus.yml:6: drive.rpdo: drive: Receive-PDO 5 not available"
    );
    assert_eq!(
        e("  tpdo:\n    1:\n      mapping:\n        - {index: 0x6041, sub_index: 3}\n"),
        "bus.yml:8: drive.tpdo.1.mapping: drive: sub-object 0x6041/3 does not exist"
    );
    assert_eq!(
        e("  tpdo:\n    1:\n      mapping:\n        - {index: 0x0005}\n"),
        "bus.yml:8: drive.tpdo.1.mapping: drive: sub-object 0x0005/0 does not exist"
    );
    assert_eq!(
        e("  rpdo:\n    1:\n      event_deadline: 100\n"),
        "bus.yml:7: drive.rpdo.1.event_deadline: an event deadline needs an event_timer beside it"
    );
    assert_eq!(
        e("  tpdo:\n    1:\n      cob_id: many\n"),
        "bus.yml:7: drive.tpdo.1.cob_id: 'many' is no integer"
    );
}

#[test]
fn check_reports_every_problem_and_node_id_clashes() {
    let yaml = "master: {node_id: 3}\n\
                a:\n  dcf: ../../examples/drive.eds\n  node_id: 2\n\
                b:\n  dcf: ../../examples/io-device.eds\n  node_id: 2\n\
                c:\n  dcf: missing.eds\n\
                d:\n  dcf: ../../examples/io-device.eds\n  node_id: 3\n";
    let bus = Bus::parse(yaml, "bus.yml").unwrap();
    let (errors, _) = check(&bus, &mut load, &|_| None, GenOptions::default());
    let lines: Vec<String> = errors.iter().map(ToString::to_string).collect();
    assert_eq!(
        lines,
        [
            "bus.yml:5: b: node-ID 2 is a's too",
            "bus.yml:9: c.dcf: cannot read missing.eds",
            "bus.yml:1: master.node_id: node-ID 3 is d's too",
        ]
    );
}

proptest::proptest! {
    /// Any numbers in any key of a slave give files or an error, never a panic.
    #[test]
    fn any_numbers_generate_or_fail(
        node in -5i64..300, hb in -1i64..70000, pdo in -2i64..600, index in -1i64..0x10010,
        sub in -1i64..300, value in proptest::num::i64::ANY, cob in proptest::num::i64::ANY,
    ) {
        let yaml = format!(
            "master: {{node_id: 1, heartbeat_producer: {hb}}}\nx:\n  dcf: ../../examples/drive.eds\n  \
             node_id: {node}\n  heartbeat_producer: {hb}\n  heartbeat_consumer: true\n  tpdo:\n    {pdo}:\n      \
             cob_id: {cob}\n      mapping:\n        - {{index: {index}, sub_index: {sub}}}\n  sdo:\n    - \
             {{index: {index}, sub_index: {sub}, value: {value}}}\n"
        );
        let _ = error(&yaml);
    }
}
