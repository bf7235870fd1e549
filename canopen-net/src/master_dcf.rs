//! The text of `master.dcf`: the master's objects in the layout dcfgen writes (CiA 306 with
//! `CompactSubObj` arrays), the slaves' PDOs mirrored, and the objects the received and sent values
//! live in (0x2000.., 0x2200..).

use crate::master::{first_mapped, line, pdos, Master};
use crate::slave::Slave;

macro_rules! w {
    ($out:expr, $($arg:tt)*) => { line($out, format_args!($($arg)*)) };
}

fn var(out: &mut String, index: &str, name: &str, dt: u16, access: &str, default: Option<String>) {
    w!(out, "");
    w!(out, "[{index}]");
    w!(out, "ParameterName={name}");
    w!(out, "DataType=0x{dt:04X}");
    w!(out, "AccessType={access}");
    if let Some(d) = default {
        w!(out, "DefaultValue={d}");
    }
}

fn array(
    out: &mut String,
    index: &str,
    name: &str,
    dt: u16,
    access: &str,
    default: Option<&str>,
    compact: usize,
) {
    w!(out, "");
    w!(out, "[{index}]");
    w!(out, "ParameterName={name}");
    w!(out, "ObjectType=0x08");
    w!(out, "DataType=0x{dt:04X}");
    w!(out, "AccessType={access}");
    if let Some(d) = default {
        w!(out, "DefaultValue={d}");
    }
    w!(out, "CompactSubObj={compact}");
}

fn values(out: &mut String, index: &str, entries: &[(String, String)]) {
    w!(out, "");
    w!(out, "[{index}Value]");
    w!(out, "NrOfEntries={}", entries.len());
    for (k, v) in entries {
        w!(out, "{k}={v}");
    }
}

fn record_head(out: &mut String, name: &str, subs: usize, title: &str, dt: &str) {
    w!(out, "");
    w!(out, "[{name}]");
    w!(out, "SubNumber={subs}");
    w!(out, "ParameterName={title}");
    w!(out, "ObjectType={dt}");
}

fn sub(
    out: &mut String,
    name: &str,
    sub: &str,
    title: &str,
    dt: u16,
    access: &str,
    default: Option<String>,
) {
    w!(out, "");
    w!(out, "[{name}sub{sub}]");
    w!(out, "ParameterName={title}");
    w!(out, "DataType=0x{dt:04X}");
    w!(out, "AccessType={access}");
    if let Some(d) = default {
        w!(out, "DefaultValue={d}");
    }
}

/// The text of `master.dcf`.
pub(crate) fn render(m: &Master, slaves: &[Slave], remote_pdo: bool) -> String {
    let mut out = String::new();
    let o = &mut out;
    let software_update = slaves.iter().any(|s| !s.software_file.is_empty());
    let configuration_update = slaves.iter().any(|s| !s.configuration_file.is_empty());
    let nrpdo = pdos(slaves, true).len();
    let ntpdo = pdos(slaves, false).len();
    head(o, m, nrpdo, ntpdo);
    let mut n = 8;
    w!(o, "[OptionalObjects]");
    w!(
        o,
        "SupportedObjects={}",
        8 + usize::from(m.heartbeat_consumer)
            + 5
            + 2 * nrpdo
            + 2 * ntpdo
            + usize::from(configuration_update)
            + 2
            + usize::from(software_update)
            + 10
    );
    for (i, idx) in [
        "1003", "1005", "1006", "1007", "1012", "1013", "1014", "1015",
    ]
    .iter()
    .enumerate()
    {
        w!(o, "{}=0x{idx}", i + 1);
    }
    let mut list = Vec::new();
    if m.heartbeat_consumer {
        list.push(0x1016);
    }
    list.extend([0x1017, 0x1019, 0x1028, 0x1029, 0x102A]);
    list.extend((0..nrpdo as u32).map(|i| 0x1400 + i));
    list.extend((0..nrpdo as u32).map(|i| 0x1600 + i));
    list.extend((0..ntpdo as u32).map(|i| 0x1800 + i));
    list.extend((0..ntpdo as u32).map(|i| 0x1A00 + i));
    if configuration_update {
        list.push(0x1F22);
    }
    list.extend([0x1F25, 0x1F55]);
    if software_update {
        list.push(0x1F58);
    }
    list.extend([
        0x1F80, 0x1F81, 0x1F82, 0x1F84, 0x1F85, 0x1F86, 0x1F87, 0x1F88, 0x1F89, 0x1F8A,
    ]);
    for idx in list {
        n += 1;
        w!(o, "{n}=0x{idx:04X}");
    }
    w!(o, "");
    manufacturer_list(o, slaves, remote_pdo, nrpdo, ntpdo);
    communication(o, m, slaves);
    mirrored(o, slaves);
    commissioning(o, m, slaves, configuration_update, software_update);
    application(o, slaves);
    if remote_pdo {
        remote(o, slaves);
    }
    out
}

fn head(o: &mut String, m: &Master, nrpdo: usize, ntpdo: usize) {
    let [vendor, product, revision, serial] = m.identity;
    for l in [
        "[DeviceComissioning]".to_string(),
        format!("NodeID={}", m.node_id),
        "NodeName=".into(),
        "NodeRefd=".into(),
        format!("Baudrate={}", m.baudrate),
        "NetNumber=1".into(),
        "NetworkName=".into(),
        "NetRefd=".into(),
        "CANopenManager=1".into(),
        format!("LSS_SerialNumber=0x{serial:08X}"),
        String::new(),
        "[DeviceInfo]".into(),
        "VendorName=".into(),
        format!("VendorNumber=0x{vendor:08X}"),
        "ProductName=".into(),
        format!("ProductNumber=0x{product:08X}"),
        format!("RevisionNumber=0x{revision:08X}"),
        "OrderCode=".into(),
    ] {
        w!(o, "{l}");
    }
    for rate in [10, 20, 50, 125, 250, 500, 800, 1000] {
        w!(o, "BaudRate_{rate}=1");
    }
    for l in [
        "SimpleBootUpMaster=1",
        "SimpleBootUpSlave=0",
        "Granularity=1",
        "DynamicChannelsSupported=0",
        "GroupMessaging=0",
    ] {
        w!(o, "{l}");
    }
    w!(o, "NrOfRxPDO={nrpdo}");
    w!(o, "NrOfTxPDO={ntpdo}");
    w!(o, "LSS_Supported=1");
    w!(o, "");
    w!(o, "[DummyUsage]");
    for d in [
        1, 2, 3, 4, 5, 6, 7, 0x10, 0x12, 0x13, 0x14, 0x15, 0x16, 0x18, 0x19, 0x1A, 0x1B,
    ] {
        w!(o, "Dummy{d:04X}=1");
    }
    w!(o, "");
    w!(o, "[MandatoryObjects]");
    w!(o, "SupportedObjects=3");
    w!(o, "1=0x1000");
    w!(o, "2=0x1001");
    w!(o, "3=0x1018");
    w!(o, "");
}

/// The indices of the application objects: 0x2000 + n for each received PDO n with a new entry.
fn app_indices(slaves: &[Slave], tpdo: bool, base: u32) -> Vec<u32> {
    let mut idx = Vec::new();
    let mut n = 0;
    for s in slaves {
        let mut mapped = Vec::new();
        for (_, p) in if tpdo { &s.tpdo } else { &s.rpdo } {
            n += 1;
            if !first_mapped(p, &mut mapped).is_empty() {
                idx.push(base + n - 1);
            }
        }
    }
    idx
}

fn manufacturer_list(
    o: &mut String,
    slaves: &[Slave],
    remote_pdo: bool,
    nrpdo: usize,
    ntpdo: usize,
) {
    let ridx = app_indices(slaves, true, 0x2000);
    let tidx = app_indices(slaves, false, 0x2200);
    w!(o, "[ManufacturerObjects]");
    let extra = if remote_pdo { 2 * nrpdo + 2 * ntpdo } else { 0 };
    w!(o, "SupportedObjects={}", ridx.len() + tidx.len() + extra);
    let mut list: Vec<u32> = ridx.into_iter().chain(tidx).collect();
    if remote_pdo {
        for (base, count) in [
            (0x5800, nrpdo),
            (0x5A00, nrpdo),
            (0x5C00, ntpdo),
            (0x5E00, ntpdo),
        ] {
            list.extend((0..count as u32).map(|i| base + i));
        }
    }
    for (i, idx) in list.iter().enumerate() {
        w!(o, "{}=0x{idx:04X}", i + 1);
    }
}

fn communication(o: &mut String, m: &Master, slaves: &[Slave]) {
    var(o, "1000", "Device type", 7, "ro", Some("0x00000000".into()));
    var(o, "1001", "Error register", 5, "ro", None);
    array(o, "1003", "Pre-defined error field", 7, "ro", None, 254);
    var(
        o,
        "1005",
        "COB-ID SYNC message",
        7,
        "rw",
        Some("0x40000080".into()),
    );
    var(
        o,
        "1006",
        "Communication cycle period",
        7,
        "rw",
        Some(m.sync[0].to_string()),
    );
    var(
        o,
        "1007",
        "Synchronous window length",
        7,
        "rw",
        Some(m.sync[1].to_string()),
    );
    var(
        o,
        "1012",
        "COB-ID time stamp object",
        7,
        "rw",
        Some(format!("0x{:08X}", m.time_cob_id)),
    );
    w!(o, "");
    w!(o, "[1013]\nParameterName=High resolution time stamp\nDataType=0x0007\nAccessType=rw\nPDOMapping=1");
    var(
        o,
        "1014",
        "COB-ID EMCY",
        7,
        "rw",
        Some("$NODEID+0x80".into()),
    );
    var(
        o,
        "1015",
        "Inhibit time EMCY",
        6,
        "rw",
        Some(m.emcy_inhibit_time.to_string()),
    );
    if m.heartbeat_consumer {
        array(o, "1016", "Consumer heartbeat time", 7, "rw", None, 127);
        let entries: Vec<_> = slaves
            .iter()
            .filter(|s| s.heartbeat_producer != 0)
            .enumerate()
            .map(|(i, s)| {
                let t = u32::from(s.consumer_time());
                (
                    (i + 1).to_string(),
                    format!("0x{:08X}", ((s.node_id & 0xFF) << 16) | t),
                )
            })
            .collect();
        values(o, "1016", &entries);
    }
    identity(o, m, slaves);
}

fn identity(o: &mut String, m: &Master, slaves: &[Slave]) {
    var(
        o,
        "1017",
        "Producer heartbeat time",
        6,
        "rw",
        Some(m.heartbeat_producer.to_string()),
    );
    record_head(o, "1018", 5, "Identity Object", "0x09");
    sub(
        o,
        "1018",
        "0",
        "Highest sub-index supported",
        5,
        "const",
        Some("4".into()),
    );
    sub(
        o,
        "1018",
        "1",
        "Vendor-ID",
        7,
        "ro",
        Some(format!("0x{:08X}", m.identity[0])),
    );
    sub(
        o,
        "1018",
        "2",
        "Product code",
        7,
        "ro",
        Some(format!("0x{:08X}", m.identity[1])),
    );
    sub(
        o,
        "1018",
        "3",
        "Revision number",
        7,
        "ro",
        Some(format!("0x{:08X}", m.identity[2])),
    );
    sub(o, "1018", "4", "Serial number", 7, "ro", None);
    var(
        o,
        "1019",
        "Synchronous counter overflow value",
        5,
        "rw",
        Some(m.sync[2].to_string()),
    );
    emergency(o, m, slaves);
}

fn emergency(o: &mut String, m: &Master, slaves: &[Slave]) {
    array(
        o,
        "1028",
        "Emergency consumer object",
        7,
        "rw",
        Some("0x80000000"),
        127,
    );
    let emcy: Vec<_> = slaves
        .iter()
        .filter(|s| s.emcy_cob_id & 0x8000_0000 == 0)
        .map(|s| (s.node_id.to_string(), format!("0x{:08X}", s.emcy_cob_id)))
        .collect();
    values(o, "1028", &emcy);
    array(o, "1029", "Error behavior object", 5, "rw", None, 254);
    let mut eb = m.error_behavior.clone();
    eb.sort();
    let eb: Vec<_> = eb
        .iter()
        .map(|(s, v)| (s.to_string(), format!("0x{v:02X}")))
        .collect();
    values(o, "1029", &eb);
    var(
        o,
        "102A",
        "NMT inhibit time",
        6,
        "rw",
        Some(m.nmt_inhibit_time.to_string()),
    );
}

/// One sub-object of a record: sub-index, name, data type, access and default value.
type SubRow = (
    &'static str,
    &'static str,
    u16,
    &'static str,
    Option<String>,
);

/// A record `name` with `title`: sub-index 0 (the highest sub-index, `rows` counted), then its
/// sub-objects `rows`, in order.
fn record(o: &mut String, name: &str, title: &str, rows: Vec<SubRow>) {
    record_head(o, name, rows.len() + 1, title, "0x09");
    let highest = Some(rows.len().to_string());
    sub(
        o,
        name,
        "0",
        "highest sub-index supported",
        5,
        "const",
        highest,
    );
    for (k, t, dt, access, default) in rows {
        sub(o, name, k, t, dt, access, default);
    }
}

/// The master's PDOs: its RPDOs mirror the slaves' TPDOs, its TPDOs the slaves' RPDOs.
fn mirrored(o: &mut String, slaves: &[Slave]) {
    for (n, (_, _, p)) in pdos(slaves, true).iter().enumerate() {
        let rows: Vec<SubRow> = vec![
            (
                "1",
                "COB-ID used by RPDO",
                7,
                "rw",
                Some(format!("0x{:08X}", p.cob_id)),
            ),
            (
                "2",
                "transmission type",
                5,
                "rw",
                Some(format!("0x{:02X}", p.transmission_type)),
            ),
            ("3", "inhibit time", 6, "rw", None),
            ("4", "compatibility entry", 5, "rw", None),
            (
                "5",
                "event-timer",
                6,
                "rw",
                Some(p.event_deadline.to_string()),
            ),
        ];
        record(
            o,
            &format!("{:04X}", 0x1400 + n),
            "RPDO communication parameter",
            rows,
        );
    }
    mapping_params(o, slaves, true);
    for (n, (_, _, p)) in pdos(slaves, false).iter().enumerate() {
        let rows: Vec<SubRow> = vec![
            (
                "1",
                "COB-ID used by TPDO",
                7,
                "rw",
                Some(format!("0x{:08X}", p.cob_id)),
            ),
            (
                "2",
                "transmission type",
                5,
                "rw",
                Some(format!("0x{:02X}", p.transmission_type)),
            ),
            (
                "3",
                "inhibit time",
                6,
                "rw",
                Some(p.inhibit_time.to_string()),
            ),
            ("4", "reserved", 5, "rw", None),
            ("5", "event timer", 6, "rw", Some(p.event_timer.to_string())),
            (
                "6",
                "SYNC start value",
                5,
                "rw",
                Some(p.sync_start.to_string()),
            ),
        ];
        record(
            o,
            &format!("{:04X}", 0x1800 + n),
            "TPDO communication parameter",
            rows,
        );
    }
    mapping_params(o, slaves, false);
}

fn mapping_params(o: &mut String, slaves: &[Slave], tpdo: bool) {
    let (base, app, title) = if tpdo {
        (0x1600, 0x2000, "RPDO")
    } else {
        (0x1A00, 0x2200, "TPDO")
    };
    let mut n = 0;
    for s in slaves {
        let mut seen: Vec<((u16, u8), String)> = Vec::new();
        for (_, p) in if tpdo { &s.tpdo } else { &s.rpdo } {
            let name = format!("{:04X}", base + n);
            n += 1;
            let mut i = 0;
            w!(o, "");
            w!(o, "[{name}]");
            w!(o, "ParameterName={title} mapping parameter");
            w!(o, "ObjectType=0x09");
            w!(o, "DataType=0x0007");
            w!(o, "AccessType=rw");
            w!(o, "CompactSubObj={}", p.mapping.len());
            let mut entries = Vec::new();
            for (j, (_, m)) in p.mapping.iter().enumerate() {
                let k = (m.index, m.sub);
                if !seen.iter().any(|(x, _)| *x == k) {
                    i += 1;
                    seen.push((k, format!("0x{:04X}{i:02X}{:02X}", app + n - 1, m.bits)));
                }
                let v = seen
                    .iter()
                    .find(|(x, _)| *x == k)
                    .map(|(_, v)| v.clone())
                    .unwrap_or_default();
                entries.push(((j + 1).to_string(), v));
            }
            values(o, &name, &entries);
        }
    }
}

fn commissioning(
    o: &mut String,
    m: &Master,
    slaves: &[Slave],
    configuration: bool,
    software: bool,
) {
    let files = |o: &mut String, index: &str, title: &str, file: &dyn Fn(&Slave) -> &str| {
        record_head(o, index, 128, title, "0x08");
        sub(
            o,
            index,
            "0",
            "Highest sub-index supported",
            5,
            "const",
            Some("127".into()),
        );
        for i in 1..=127u32 {
            let name = if index == "1F22" {
                format!("Node-ID {i}")
            } else {
                format!("Program data of node-ID {i}")
            };
            sub(o, index, &format!("{i:X}"), &name, 0x0F, "ro", None);
            for s in slaves
                .iter()
                .filter(|s| s.node_id == i && !file(s).is_empty())
            {
                w!(o, "UploadFile={}", file(s));
            }
        }
    };
    if configuration {
        files(o, "1F22", "Concise DCF", &|s| &s.configuration_file);
    }
    array(o, "1F25", "Configuration request", 5, "wo", None, 127);
    array(
        o,
        "1F55",
        "Expected software identification",
        7,
        "rw",
        None,
        127,
    );
    if software {
        files(o, "1F58", "Program data", &|s| &s.software_file);
    }
    let v = m.startup_word();
    var(
        o,
        "1F80",
        "NMT startup",
        7,
        "rw",
        Some(format!("0x{v:08X}")),
    );
    array(o, "1F81", "NMT slave assignment", 7, "rw", None, 127);
    let assign: Vec<_> = slaves
        .iter()
        .map(|s| (s.node_id.to_string(), format!("0x{:08X}", s.assignment())))
        .collect();
    values(o, "1F81", &assign);
    array(o, "1F82", "Request NMT", 5, "rw", None, 127);
    let ident = |o: &mut String,
                 index: &str,
                 title: &str,
                 v: &dyn Fn(&Slave) -> u32,
                 shown: &dyn Fn(&Slave) -> bool| {
        array(o, index, title, 7, "rw", None, 127);
        w!(o, "");
        w!(o, "[{index}Value]");
        w!(
            o,
            "NrOfEntries={}",
            slaves.iter().filter(|s| v(s) != 0).count()
        );
        for s in slaves.iter().filter(|s| v(s) != 0 && shown(s)) {
            w!(o, "{}=0x{:08X}", s.node_id, v(s));
        }
    };
    ident(
        o,
        "1F84",
        "Device type identification",
        &|s| s.device_type,
        &|_| true,
    );
    ident(
        o,
        "1F85",
        "Vendor identification",
        &|s| s.vendor_id,
        &|_| true,
    );
    ident(o, "1F86", "Product code", &|s| s.product_code, &|s| {
        s.has_identity(2)
    });
    array(o, "1F87", "Revision_number", 7, "rw", None, 127);
    array(o, "1F88", "Serial number", 7, "rw", None, 127);
    var(
        o,
        "1F89",
        "Boot time",
        7,
        "rw",
        Some(m.boot_time.to_string()),
    );
    array(o, "1F8A", "Restore configuration", 5, "rw", None, 127);
    let restore: Vec<_> = slaves
        .iter()
        .filter(|s| s.restore_configuration != 0)
        .map(|s| {
            (
                s.node_id.to_string(),
                format!("0x{:02X}", s.restore_configuration),
            )
        })
        .collect();
    values(o, "1F8A", &restore);
}

/// The objects the values of the PDOs live in: 0x2000.. for received, 0x2200.. for sent.
fn application(o: &mut String, slaves: &[Slave]) {
    for (tpdo, base, title, access) in [
        (true, 0x2000, "RPDO", "rww"),
        (false, 0x2200, "TPDO", "rwr"),
    ] {
        let mut n = 0;
        for s in slaves {
            let mut mapped = Vec::new();
            for (_, p) in if tpdo { &s.tpdo } else { &s.rpdo } {
                n += 1;
                let first = first_mapped(p, &mut mapped);
                if first.is_empty() {
                    continue;
                }
                let name = format!("{:04X}", base + n - 1);
                record_head(
                    o,
                    &name,
                    first.len() + 1,
                    &format!("Mapped application objects for {title} {n}"),
                    "0x09",
                );
                sub(
                    o,
                    &name,
                    "0",
                    "Highest sub-index supported",
                    5,
                    "const",
                    Some(first.len().to_string()),
                );
                for (i, m) in first.iter().enumerate() {
                    sub(
                        o,
                        &name,
                        &format!("{:X}", i + 1),
                        &format!("{}: {}", s.name, m.name),
                        m.data_type,
                        access,
                        None,
                    );
                    w!(o, "PDOMapping=1");
                }
            }
        }
    }
}

fn remote(o: &mut String, slaves: &[Slave]) {
    for (tpdo, num, map, word) in [
        (true, 0x5800, 0x5A00, "TPDO"),
        (false, 0x5C00, 0x5E00, "RPDO"),
    ] {
        let list = pdos(slaves, tpdo);
        for (n, (s, i, _)) in list.iter().enumerate() {
            let title = format!("Remote {word} number and node-ID");
            var(
                o,
                &format!("{:04X}", num + n),
                &title,
                7,
                "rw",
                Some(format!("0x{i:06X}{:02X}", s.node_id)),
            );
        }
        for (n, (_, _, p)) in list.iter().enumerate() {
            let name = format!("{:04X}", map + n);
            array(
                o,
                &name,
                &format!("Remote {word} mapping parameter"),
                7,
                "rw",
                None,
                p.mapping.len(),
            );
            let entries: Vec<_> = p
                .mapping
                .iter()
                .enumerate()
                .map(|(i, (_, m))| {
                    (
                        (i + 1).to_string(),
                        format!("0x{:04X}{:02X}{:02X}", m.index, m.sub, m.bits),
                    )
                })
                .collect();
            values(o, &name, &entries);
        }
    }
}
