//! The description as a whole, in the order of its parts, and the parts every description has:
//! identity, file information, CAN capabilities and commissioning.

use super::context::{hex8, joined, or_none, Cx, Key, List};
use super::dictionary::dictionary;
use super::ethercat::ethercat;
use super::{Shown, Step};
use crate::device::{CanInfo, Commissioning, DeviceDescription, FileInfo, Identity};

pub(super) fn device(cx: &mut Cx<'_>, a: &DeviceDescription, b: &DeviceDescription) {
    let DeviceDescription {
        identity,
        file_info,
        can,
        commissioning: commissioned,
        ethercat: ecat,
        dictionary: dict,
        comments,
    } = a;
    cx.within(Step::Part("identity"), |cx| {
        self::identity(cx, identity, &b.identity)
    });
    cx.within(Step::Part("file info"), |cx| {
        self::file_info(cx, file_info, &b.file_info)
    });
    cx.option(Step::Part("CAN"), can, &b.can, can_info);
    cx.option(
        Step::Part("commissioning"),
        commissioned,
        &b.commissioning,
        commissioning,
    );
    match (ecat, &b.ethercat) {
        // The EtherCAT parts are named by their own kinds (`RxPdo 0x1600`, `Sm 2`), not under `EtherCAT`.
        (Some(x), Some(y)) => ethercat(cx, x, y),
        (x, y) => cx.option(Step::Part("EtherCAT"), x, y, |_, _, _| {}),
    }
    dictionary(cx, dict, &b.dictionary);
    cx.list(
        List {
            kind: "comment",
            key: Key::Position(1),
            name: |line: &String| line.clone(),
            compare: |cx, x: &String, y: &String| cx.text("text", x, y),
        },
        comments,
        &b.comments,
    );
}

fn identity(cx: &mut Cx<'_>, a: &Identity, b: &Identity) {
    let Identity {
        vendor_id,
        vendor_name,
        product_code,
        revision,
        product_name,
        order_code,
        hardware_version,
        software_version,
        firmware_version,
    } = a;
    cx.field("vendor ID", vendor_id, &b.vendor_id, hex8);
    cx.text("vendor name", vendor_name, &b.vendor_name);
    cx.field("product code", product_code, &b.product_code, hex8);
    cx.field("revision", revision, &b.revision, hex8);
    cx.text("product name", product_name, &b.product_name);
    cx.text("order code", order_code, &b.order_code);
    cx.text("hardware version", hardware_version, &b.hardware_version);
    cx.text("software version", software_version, &b.software_version);
    cx.text("firmware version", firmware_version, &b.firmware_version);
}

fn file_info(cx: &mut Cx<'_>, a: &FileInfo, b: &FileInfo) {
    let FileInfo {
        file_name,
        file_version,
        file_revision,
        format_version,
        description,
        creation_time,
        creation_date,
        created_by,
        modification_time,
        modification_date,
        modified_by,
    } = a;
    cx.text("file name", file_name, &b.file_name);
    cx.text("file version", file_version, &b.file_version);
    cx.text("file revision", file_revision, &b.file_revision);
    cx.text("format version", format_version, &b.format_version);
    cx.text("description", description, &b.description);
    cx.text("creation time", creation_time, &b.creation_time);
    cx.text("creation date", creation_date, &b.creation_date);
    cx.text("created by", created_by, &b.created_by);
    cx.text("modification time", modification_time, &b.modification_time);
    cx.text("modification date", modification_date, &b.modification_date);
    cx.text("modified by", modified_by, &b.modified_by);
}

fn can_info(cx: &mut Cx<'_>, a: &CanInfo, b: &CanInfo) {
    let CanInfo {
        baud_rates,
        simple_boot_up_master,
        simple_boot_up_slave,
        granularity,
        dynamic_channels,
        group_messaging,
        nr_of_rx_pdo,
        nr_of_tx_pdo,
        lss_supported,
        dummy_usage,
    } = a;
    cx.field("bit rates", baud_rates, &b.baud_rates, |v| {
        joined(v, |r| format!("{r} kbit/s"))
    });
    cx.plain(
        "simple boot-up master",
        simple_boot_up_master,
        &b.simple_boot_up_master,
    );
    cx.plain(
        "simple boot-up slave",
        simple_boot_up_slave,
        &b.simple_boot_up_slave,
    );
    cx.plain("granularity", granularity, &b.granularity);
    cx.plain("dynamic channels", dynamic_channels, &b.dynamic_channels);
    cx.plain("group messaging", group_messaging, &b.group_messaging);
    cx.plain("RPDOs", nr_of_rx_pdo, &b.nr_of_rx_pdo);
    cx.plain("TPDOs", nr_of_tx_pdo, &b.nr_of_tx_pdo);
    cx.plain("LSS", lss_supported, &b.lss_supported);
    cx.field("dummy usage", dummy_usage, &b.dummy_usage, |v| {
        joined(v, |t| format!("0x{t:04X}"))
    });
}

fn commissioning(cx: &mut Cx<'_>, a: &Commissioning, b: &Commissioning) {
    let Commissioning {
        node_id,
        node_name,
        baud_rate,
        net_number,
        network_name,
        canopen_manager,
        lss_serial_number,
    } = a;
    cx.field("node ID", node_id, &b.node_id, |v| {
        Shown::Plain(or_none(v, u8::to_string))
    });
    cx.text("node name", node_name, &b.node_name);
    cx.field("bit rate", baud_rate, &b.baud_rate, |r| {
        Shown::Plain(format!("{r} kbit/s"))
    });
    cx.plain("net number", net_number, &b.net_number);
    cx.text("network name", network_name, &b.network_name);
    cx.plain("CANopen manager", canopen_manager, &b.canopen_manager);
    cx.field(
        "LSS serial number",
        lss_serial_number,
        &b.lss_serial_number,
        hex8,
    );
}
