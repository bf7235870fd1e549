//! `esi-gen diff`: two descriptions compared device by device ([`od::diff`]), as text or JSON lines.
//!
//! Text: one line per difference, `- PLACE NAME` for a part only the first file has, `+ PLACE NAME` for
//! one only the second has, `~ PLACE FIELD: A -> B` for a field that differs. When several devices are
//! compared, a device only one file has is one `- device …` / `+ device …` line, and the differences of
//! each pair of devices are indented under a `device …:` header; pairs without differences print
//! nothing.
//!
//! JSON: one object per line for each difference, with `device` (`name`, `product_code`, `revision`: the
//! first file's device, or the second's for a device only it has), `change` (`only_in_a`, `only_in_b`,
//! `changed`), `path` (the steps of the place as text; empty for a whole device), `index` and `sub` for a
//! place in the dictionary, `name` for a part only one side has, and `field`, `a`, `b` for a change (the
//! values as the text shows them, without quotes).

use std::io::Write;

use od::device::DeviceDescription;
use od::diff::{Change, Difference, Pairing};
use serde::Serialize;

use crate::{device_name, load_selected, write_out, DiffArgs, Error, Outcome};

/// The differences between the devices of two files, in the order they are printed.
#[derive(Debug, Default)]
pub struct Comparison<'d> {
    /// True when the files hold several devices, so each is named.
    pub several: bool,
    /// What was found, device by device (pairs without differences left out).
    pub devices: Vec<DeviceChange<'d>>,
}

/// What was found for one device.
#[derive(Debug)]
pub enum DeviceChange<'d> {
    /// A device only the first file has.
    OnlyInA(&'d DeviceDescription),
    /// A device only the second file has.
    OnlyInB(&'d DeviceDescription),
    /// A device of the first file, and how its like in the second differs from it.
    Differs(&'d DeviceDescription, Vec<Difference>),
}

impl<'d> Comparison<'d> {
    /// Pairs and compares the devices of `a` and `b`.
    pub fn of(a: &'d [DeviceDescription], b: &'d [DeviceDescription]) -> Comparison<'d> {
        let devices = od::diff::pair_devices(a, b)
            .into_iter()
            .filter_map(|p| match p {
                Pairing::OnlyInA(i) => Some(DeviceChange::OnlyInA(&a[i])),
                Pairing::OnlyInB(j) => Some(DeviceChange::OnlyInB(&b[j])),
                Pairing::Both(i, j) => {
                    let found = od::diff::diff_devices(&a[i], &b[j]);
                    (!found.is_empty()).then(|| DeviceChange::Differs(&a[i], found))
                }
            })
            .collect();
        Comparison {
            several: a.len() > 1 || b.len() > 1,
            devices,
        }
    }

    /// True when nothing differs.
    pub fn is_equal(&self) -> bool {
        self.devices.is_empty()
    }

    /// The text form: one line per difference.
    pub fn text(&self) -> String {
        let mut out = String::new();
        for change in &self.devices {
            match change {
                DeviceChange::OnlyInA(d) => out.push_str(&format!("- device {}\n", title(d))),
                DeviceChange::OnlyInB(d) => out.push_str(&format!("+ device {}\n", title(d))),
                DeviceChange::Differs(d, found) => {
                    let indent = if self.several {
                        out.push_str(&format!("device {}:\n", title(d)));
                        "  "
                    } else {
                        ""
                    };
                    for x in found {
                        out.push_str(&format!("{indent}{x}\n"));
                    }
                }
            }
        }
        out
    }

    /// The JSON form: one object per line for each difference.
    pub fn json(&self) -> String {
        let mut out = String::new();
        let mut line = |record: Record<'_>| {
            // A struct of strings, numbers and options always serialises.
            out.push_str(&serde_json::to_string(&record).unwrap_or_default());
            out.push('\n');
        };
        for change in &self.devices {
            match change {
                DeviceChange::OnlyInA(d) => line(Record::device(d, "only_in_a")),
                DeviceChange::OnlyInB(d) => line(Record::device(d, "only_in_b")),
                DeviceChange::Differs(d, found) => {
                    for x in found {
                        line(Record::difference(d, x));
                    }
                }
            }
        }
        out
    }
}

/// A device as a header names it: `EL1008 (product code 0x03F03052, revision 0x00100000)`.
fn title(d: &DeviceDescription) -> String {
    format!(
        "{} (product code 0x{:08X}, revision 0x{:08X})",
        device_name(d),
        d.identity.product_code,
        d.identity.revision
    )
}

#[derive(Serialize)]
struct DeviceRef<'a> {
    name: &'a str,
    product_code: String,
    revision: String,
}

#[derive(Serialize)]
struct Record<'a> {
    device: DeviceRef<'a>,
    change: &'static str,
    path: Vec<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    index: Option<u16>,
    #[serde(skip_serializing_if = "Option::is_none")]
    sub: Option<u8>,
    #[serde(skip_serializing_if = "Option::is_none")]
    name: Option<&'a str>,
    #[serde(skip_serializing_if = "Option::is_none")]
    field: Option<&'static str>,
    #[serde(skip_serializing_if = "Option::is_none")]
    a: Option<&'a str>,
    #[serde(skip_serializing_if = "Option::is_none")]
    b: Option<&'a str>,
}

impl<'a> Record<'a> {
    fn base(d: &'a DeviceDescription, change: &'static str) -> Record<'a> {
        Record {
            device: DeviceRef {
                name: device_name(d),
                product_code: format!("0x{:08X}", d.identity.product_code),
                revision: format!("0x{:08X}", d.identity.revision),
            },
            change,
            path: Vec::new(),
            index: None,
            sub: None,
            name: None,
            field: None,
            a: None,
            b: None,
        }
    }

    /// A whole device only one file has.
    fn device(d: &'a DeviceDescription, change: &'static str) -> Record<'a> {
        Record {
            name: Some(device_name(d)),
            ..Record::base(d, change)
        }
    }

    fn difference(d: &'a DeviceDescription, x: &'a Difference) -> Record<'a> {
        let (change, name, field, a, b) = match &x.change {
            Change::OnlyInA(name) => ("only_in_a", Some(name.as_str()), None, None, None),
            Change::OnlyInB(name) => ("only_in_b", Some(name.as_str()), None, None, None),
            Change::Changed { field, a, b } => (
                "changed",
                None,
                Some(*field),
                Some(a.as_str()),
                Some(b.as_str()),
            ),
        };
        Record {
            path: x.path.iter().map(|s| s.to_string()).collect(),
            index: x.index(),
            sub: x.sub(),
            name,
            field,
            a,
            b,
            ..Record::base(d, change)
        }
    }
}

/// Runs `esi-gen diff`: exit 0 when the descriptions are equal, 1 when they differ.
pub fn run(args: &DiffArgs, out: &mut dyn Write) -> Outcome {
    let load = |path| -> Result<Vec<DeviceDescription>, Error> {
        let (_, devices) = load_selected(path, args.device.as_deref())?;
        if devices.is_empty() {
            return Err(Error::NoDevice(path.to_path_buf()));
        }
        Ok(devices)
    };
    let a = load(&args.a)?;
    let b = load(&args.b)?;
    let comparison = Comparison::of(&a, &b);
    let mut text = if args.json {
        comparison.json()
    } else {
        comparison.text()
    };
    let mut equal = comparison.is_equal();
    if args.all {
        let parts = file_parts(&args.a, &args.b)?;
        equal &= parts.is_empty();
        for p in &parts {
            text.push_str(&if args.json { p.json() } else { p.text() });
        }
    }
    write_out(out, &text)?;
    Ok(if equal { 0 } else { 1 })
}

/// A difference in the parts of two files the model does not hold.
#[derive(Debug, PartialEq, Eq)]
pub enum FilePart {
    /// A part only the first file has.
    OnlyInA(od::carry::Unheld),
    /// A part only the second file has.
    OnlyInB(od::carry::Unheld),
    /// A part both have, with its text in each.
    Changed(String, String, String),
}

impl FilePart {
    fn text(&self) -> String {
        match self {
            FilePart::OnlyInA(u) => format!("- file {}\n", u.path),
            FilePart::OnlyInB(u) => format!("+ file {}\n", u.path),
            FilePart::Changed(path, a, b) => {
                format!(
                    "~ file {path}: {} -> {}\n",
                    crate::clip(a, 60),
                    crate::clip(b, 60)
                )
            }
        }
    }

    fn json(&self) -> String {
        let v = match self {
            FilePart::OnlyInA(u) => {
                serde_json::json!({"change": "only_in_a", "file_part": u.path, "a": u.text})
            }
            FilePart::OnlyInB(u) => {
                serde_json::json!({"change": "only_in_b", "file_part": u.path, "b": u.text})
            }
            FilePart::Changed(path, a, b) => {
                serde_json::json!({"change": "changed", "file_part": path, "a": a, "b": b})
            }
        };
        format!("{v}\n")
    }
}

/// The differences of the parts of files `a` and `b` that their models do not hold, by path; none
/// when the files are of different families.
pub fn file_parts(a: &std::path::Path, b: &std::path::Path) -> Result<Vec<FilePart>, Error> {
    let unheld = |path: &std::path::Path| -> Result<Option<(od::load::Format, Vec<od::carry::Unheld>)>, Error> {
        let bytes = od::load::read_limited(path, od::load::MAX_FILE_BYTES)?;
        let (format, devices) = od::load::load(path)?;
        Ok(od::carry::unheld_in_file(&bytes, format, &devices)
            .ok()
            .map(|u| (format, u)))
    };
    let (Some((fa, ua)), Some((fb, ub))) = (unheld(a)?, unheld(b)?) else {
        return Ok(Vec::new());
    };
    if !od::carry::same_family(fa, fb) {
        return Ok(Vec::new());
    }
    let in_a: std::collections::HashSet<&str> = ua.iter().map(|x| x.path.as_str()).collect();
    let in_b: std::collections::HashMap<&str, &od::carry::Unheld> =
        ub.iter().map(|y| (y.path.as_str(), y)).collect();
    let mut out = Vec::new();
    for x in &ua {
        match in_b.get(x.path.as_str()) {
            None => out.push(FilePart::OnlyInA(x.clone())),
            Some(y) if y.text != x.text => out.push(FilePart::Changed(
                x.path.clone(),
                x.text.clone(),
                y.text.clone(),
            )),
            Some(_) => {}
        }
    }
    for y in &ub {
        if !in_a.contains(y.path.as_str()) {
            out.push(FilePart::OnlyInB(y.clone()));
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use od::device::EthercatInfo;
    use od::object::AccessType;
    use od::types::DataType;
    use od::{Object, SubObject, Value};

    fn dev(name: &str, code: u32, revision: u32) -> DeviceDescription {
        let mut d = DeviceDescription::default();
        d.identity.order_code = name.into();
        d.identity.product_code = code;
        d.identity.revision = revision;
        d.dictionary.insert(Object::var(
            0x1008,
            SubObject::new("Device name", DataType::VisibleString, AccessType::Ro)
                .with_default(Value::String(name.into())),
        ));
        d
    }

    /// Two files: EL1008 in both (its name entry changed), EL1004 only in the first, DemoA in both
    /// unchanged, EK1100 only in the second.
    fn files() -> (Vec<DeviceDescription>, Vec<DeviceDescription>) {
        let a = vec![
            dev("EL1008", 0x03F0_3052, 0x0010_0000),
            dev("EL1004", 0x03EC_3052, 0x0010_0000),
            dev("DemoA", 0, 0),
        ];
        let mut b = vec![
            dev("EK1100", 0x044C_2C52, 0x0011_0000),
            dev("DemoA", 0, 0),
            dev("EL1008", 0x03F0_3052, 0x0010_0000),
        ];
        let e = b[2].dictionary.object_mut(0x1008).unwrap();
        e.subs.get_mut(&0).unwrap().value = b"EL1008-0000".to_vec();
        b[2].ethercat = Some(EthercatInfo {
            group_type: "DigIn".into(),
            ..EthercatInfo::default()
        });
        (a, b)
    }

    #[test]
    fn several_devices_are_named_and_their_differences_indented() {
        let (a, b) = files();
        let c = Comparison::of(&a, &b);
        assert!(c.several);
        assert!(!c.is_equal());
        assert_eq!(
            c.text(),
            "device EL1008 (product code 0x03F03052, revision 0x00100000):\n\
             \x20 + EtherCAT\n\
             \x20 ~ 0x1008:00 value: \"EL1008\" -> \"EL1008-0000\"\n\
             - device EL1004 (product code 0x03EC3052, revision 0x00100000)\n\
             + device EK1100 (product code 0x044C2C52, revision 0x00110000)\n"
        );
        assert_eq!(
            c.json(),
            concat!(
                r#"{"device":{"name":"EL1008","product_code":"0x03F03052","revision":"0x00100000"},"#,
                r#""change":"only_in_b","path":["EtherCAT"],"name":""}"#,
                "\n",
                r#"{"device":{"name":"EL1008","product_code":"0x03F03052","revision":"0x00100000"},"#,
                r#""change":"changed","path":["0x1008:00"],"index":4104,"sub":0,"field":"value","#,
                r#""a":"EL1008","b":"EL1008-0000"}"#,
                "\n",
                r#"{"device":{"name":"EL1004","product_code":"0x03EC3052","revision":"0x00100000"},"#,
                r#""change":"only_in_a","path":[],"name":"EL1004"}"#,
                "\n",
                r#"{"device":{"name":"EK1100","product_code":"0x044C2C52","revision":"0x00110000"},"#,
                r#""change":"only_in_b","path":[],"name":"EK1100"}"#,
                "\n",
            )
        );
    }

    #[test]
    fn one_device_each_is_compared_without_a_header() {
        let (a, b) = files();
        let c = Comparison::of(&a[1..2], &b[..1]);
        assert!(!c.several);
        assert_eq!(
            c.text(),
            "~ identity product code: 0x03EC3052 -> 0x044C2C52\n\
             ~ identity revision: 0x00100000 -> 0x00110000\n\
             ~ identity order code: \"EL1004\" -> \"EK1100\"\n\
             ~ 0x1008:00 default: \"EL1004\" -> \"EK1100\"\n\
             ~ 0x1008:00 value: \"EL1004\" -> \"EK1100\"\n"
        );
        let json = c.json();
        assert_eq!(json.lines().count(), 5);
        assert_eq!(
            json.lines().next().unwrap(),
            r#"{"device":{"name":"EL1004","product_code":"0x03EC3052","revision":"0x00100000"},"change":"changed","path":["identity"],"field":"product code","a":"0x03EC3052","b":"0x044C2C52"}"#
        );
        let mut b0 = a[0].clone();
        b0.dictionary.remove(0x1008);
        let c = Comparison::of(&a[..1], std::slice::from_ref(&b0));
        assert_eq!(c.text(), "- 0x1008 Device name\n");
        assert_eq!(
            c.json(),
            r#"{"device":{"name":"EL1008","product_code":"0x03F03052","revision":"0x00100000"},"change":"only_in_a","path":["0x1008"],"index":4104,"name":"Device name"}"#
                .to_string()
                + "\n"
        );
    }

    #[test]
    fn one_file_of_several_devices_names_the_devices() {
        let (a, b) = files();
        let one_of = |c: Comparison<'_>| (c.several, c.text());
        let el1004 = "- device EL1004 (product code 0x03EC3052, revision 0x00100000)\n";
        assert_eq!(
            one_of(Comparison::of(&a[..2], &a[..1])),
            (true, el1004.to_string())
        );
        assert_eq!(
            one_of(Comparison::of(&b[1..2], &a[1..])),
            (true, el1004.replace('-', "+"))
        );
    }

    #[test]
    fn equal_files_print_nothing() {
        let (a, _) = files();
        let c = Comparison::of(&a, &a);
        assert!(c.is_equal());
        assert!(c.several);
        assert_eq!(c.text(), "");
        assert_eq!(c.json(), "");
    }
}
