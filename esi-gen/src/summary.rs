//! `esi-gen check`: a one-screen summary of a description and the findings of `od::validate`.

use std::fmt::Write;
use std::path::Path;

use od::device::DeviceDescription;
use od::load::Format;
use od::validate::{validate, Severity};

/// The text of a check and how many errors it found.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Report {
    /// The summary, several lines.
    pub text: String,
    /// Number of findings of severity error.
    pub errors: usize,
}

/// Summarises `devices` read from `path` in `format` and validates each.
pub fn check(path: &Path, format: Format, devices: &[DeviceDescription]) -> Report {
    let mut text = String::new();
    let mut errors = 0;
    let _ = writeln!(
        text,
        "{}: {format}, {} device(s)",
        path.display(),
        devices.len()
    );
    for dev in devices {
        let id = &dev.identity;
        let d = &dev.dictionary;
        let subs: usize = d.objects().map(|o| o.subs.len()).sum();
        let count =
            |r: std::ops::RangeInclusive<u16>| d.objects().filter(|o| r.contains(&o.index)).count();
        let _ = writeln!(text, "\n{}", crate::device_name(dev));
        if !id.product_name.is_empty() && id.product_name != id.order_code {
            let _ = writeln!(text, "  name         {}", id.product_name);
        }
        let _ = writeln!(
            text,
            "  vendor       0x{:08X} {}",
            id.vendor_id, id.vendor_name
        );
        let _ = writeln!(
            text,
            "  product code 0x{:08X}  revision 0x{:08X}",
            id.product_code, id.revision
        );
        let _ = writeln!(
            text,
            "  dictionary   {} objects, {} entries: {} communication, {} manufacturer, {} profile",
            d.len(),
            subs,
            count(0x1000..=0x1FFF),
            count(0x2000..=0x5FFF),
            count(0x6000..=0xFFFF)
        );
        let _ = writeln!(
            text,
            "  PDO mappings {} receive, {} transmit",
            count(0x1600..=0x17FF),
            count(0x1A00..=0x1BFF)
        );
        if let Some(ec) = &dev.ethercat {
            let modes: Vec<&str> = ec.op_modes.iter().map(|m| m.name.as_str()).collect();
            let _ = writeln!(
                text,
                "  EtherCAT     {} SMs, {} RxPDO, {} TxPDO, op modes: {}",
                ec.sync_managers.len(),
                ec.rx_pdos.len(),
                ec.tx_pdos.len(),
                if modes.is_empty() {
                    "none".to_string()
                } else {
                    modes.join(", ")
                }
            );
        }
        if let Some(c) = &dev.commissioning {
            let node = c
                .node_id
                .map_or_else(|| "unconfigured".to_string(), |id| id.to_string());
            let _ = writeln!(
                text,
                "  node-ID      {node}  bit rate {} kbit/s",
                c.baud_rate
            );
        }
        let findings = validate(dev);
        let e = findings
            .iter()
            .filter(|f| f.severity == Severity::Error)
            .count();
        errors += e;
        let _ = writeln!(
            text,
            "  findings     {e} error(s), {} warning(s)",
            findings.len() - e
        );
        for f in findings.iter().take(20) {
            let _ = writeln!(text, "    {f}");
        }
        if findings.len() > 20 {
            let _ = writeln!(text, "    … {} more", findings.len() - 20);
        }
    }
    Report { text, errors }
}
