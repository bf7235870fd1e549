//! `--device`: picking one device of a file that holds several, by name or product code and, where a
//! file holds several revisions of a device, by revision.
//!
//! The syntax is `WHAT[@REVISION]`: `WHAT` is a type name or product name (any case) or a product code
//! (`0x04602C22`, `#x04602C22` as ESI writes it, or decimal), `REVISION` a revision number. Without a
//! revision, the newest revision of the device is taken, as EtherCAT configuration tools do when a
//! device is added by its type; a `WHAT` that matches different devices (two type names that share a
//! product code, several devices with product code 0) is refused with the list of them.

use std::path::Path;

use od::device::DeviceDescription;

use crate::{device_name, list, Error};

/// What `--device` asks for.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Selection {
    /// The name or product code, as written.
    pub what: String,
    /// The revision, when one was written after `@`.
    pub revision: Option<u32>,
}

fn number(text: &str) -> Option<u32> {
    let t = text.trim();
    let t = match t.strip_prefix("#x").or_else(|| t.strip_prefix("#X")) {
        Some(hex) => format!("0x{hex}"),
        None => t.to_string(),
    };
    od::value::parse_integer(&t).and_then(|v| u32::try_from(v).ok())
}

impl Selection {
    /// Reads `WHAT[@REVISION]`. Text after the last `@` that is no number is part of the name.
    pub fn parse(text: &str) -> Selection {
        if let Some((what, rev)) = text.rsplit_once('@') {
            if let Some(revision) = number(rev) {
                return Selection {
                    what: what.trim().to_string(),
                    revision: Some(revision),
                };
            }
        }
        Selection {
            what: text.trim().to_string(),
            revision: None,
        }
    }

    /// True when `d` has the name or product code asked for (the revision aside).
    fn names(&self, d: &DeviceDescription) -> bool {
        d.identity
            .order_code
            .trim()
            .eq_ignore_ascii_case(&self.what)
            || d.identity
                .product_name
                .trim()
                .eq_ignore_ascii_case(&self.what)
            || number(&self.what) == Some(d.identity.product_code)
    }
}

fn same_device(x: &DeviceDescription, y: &DeviceDescription) -> bool {
    x.identity.product_code == y.identity.product_code
        && device_name(x).eq_ignore_ascii_case(device_name(y))
}

/// The device of `devices` (read from `path`) that `wanted` picks.
pub fn select(
    path: &Path,
    devices: Vec<DeviceDescription>,
    wanted: &str,
) -> Result<DeviceDescription, Error> {
    let i = select_index(path, &devices, wanted)?;
    Ok(devices.into_iter().nth(i).expect("an index of devices"))
}

/// Where in `devices` (read from `path`) the device `wanted` picks is.
pub fn select_index(
    path: &Path,
    devices: &[DeviceDescription],
    wanted: &str,
) -> Result<usize, Error> {
    let selection = Selection::parse(wanted);
    let named: Vec<usize> = (0..devices.len())
        .filter(|&i| selection.names(&devices[i]))
        .collect();
    let no_match = |candidates: &[usize]| Error::NoSuchDevice {
        path: path.to_path_buf(),
        wanted: wanted.to_string(),
        available: list(candidates.iter().map(|&i| &devices[i])),
    };
    if named.is_empty() {
        return Err(no_match(&(0..devices.len()).collect::<Vec<_>>()));
    }
    let hits: Vec<usize> = match selection.revision {
        Some(r) => named
            .iter()
            .copied()
            .filter(|&i| devices[i].identity.revision == r)
            .collect(),
        None => named.clone(),
    };
    let Some(&first) = hits.first() else {
        return Err(no_match(&named));
    };
    if !hits
        .iter()
        .all(|&i| same_device(&devices[i], &devices[first]))
    {
        return Err(Error::AmbiguousDevice {
            path: path.to_path_buf(),
            wanted: wanted.to_string(),
            matches: list(hits.iter().map(|&i| &devices[i])),
        });
    }
    // The newest revision; the first of equal ones.
    let mut best = first;
    for &i in &hits {
        if devices[i].identity.revision > devices[best].identity.revision {
            best = i;
        }
    }
    Ok(best)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dev(name: &str, product: &str, code: u32, revision: u32) -> DeviceDescription {
        let mut d = DeviceDescription::default();
        d.identity.order_code = name.into();
        d.identity.product_name = product.into();
        d.identity.product_code = code;
        d.identity.revision = revision;
        d
    }

    fn file() -> Vec<DeviceDescription> {
        vec![
            dev("BK1120", "BK1120 Coupler", 0x0460_2C22, 0x0010_0000),
            dev("BK1120", "BK1120 Coupler", 0x0460_2C22, 0x0012_0000),
            dev("BK1120", "BK1120 Coupler", 0x0460_2C22, 0x0011_0000),
            dev("EK1122", "EK1122 2 port", 0x0462_2C52, 1),
            dev("EK1122-0008", "EK1122-0008 2 port", 0x0462_2C52, 1),
            dev("", "Demo", 0, 0),
            dev("", "Demo", 0, 0),
        ]
    }

    /// The revision picked, or the error's text.
    fn pick(wanted: &str) -> Result<(String, u32), String> {
        select(Path::new("f.xml"), file(), wanted)
            .map(|d| (device_name(&d).to_string(), d.identity.revision))
            .map_err(|e| e.to_string())
    }

    #[test]
    fn the_syntax_is_what_at_revision() {
        assert_eq!(
            Selection::parse(" BK1120@0x00100000"),
            Selection {
                what: "BK1120".into(),
                revision: Some(0x0010_0000)
            }
        );
        assert_eq!(
            Selection::parse("0x04602C22 @ #x00110000"),
            Selection {
                what: "0x04602C22".into(),
                revision: Some(0x0011_0000)
            }
        );
        assert_eq!(
            Selection::parse("a@b@17"),
            Selection {
                what: "a@b".into(),
                revision: Some(17)
            }
        );
        assert_eq!(
            Selection::parse("Vendor@Home "),
            Selection {
                what: "Vendor@Home".into(),
                revision: None
            }
        );
        assert_eq!(
            Selection::parse("x@0x100000000"),
            Selection {
                what: "x@0x100000000".into(),
                revision: None
            }
        );
    }

    #[test]
    fn several_revisions_give_the_newest_unless_one_is_named() {
        let newest = Ok(("BK1120".to_string(), 0x0012_0000));
        assert_eq!(pick("BK1120"), newest);
        assert_eq!(pick("bk1120 coupler"), newest);
        assert_eq!(pick("0x04602C22"), newest);
        assert_eq!(pick("#x04602c22"), newest);
        assert_eq!(pick("73411618"), newest);
        assert_eq!(
            pick("BK1120@0x00110000"),
            Ok(("BK1120".to_string(), 0x0011_0000))
        );
        assert_eq!(
            pick("0x04602C22@1048576"),
            Ok(("BK1120".to_string(), 0x0010_0000))
        );
        assert_eq!(pick("Demo"), Ok(("Demo".to_string(), 0)));
    }

    #[test]
    fn of_equal_revisions_the_first_is_taken() {
        let devices = vec![dev("Dup", "first", 5, 1), dev("Dup", "second", 5, 1)];
        let d = select(Path::new("f"), devices, "Dup").unwrap();
        assert_eq!(d.identity.product_name, "first");
    }

    #[test]
    fn what_matches_nothing_or_different_devices_is_refused_with_the_candidates() {
        assert_eq!(
            pick("BK1120@0x00130000"),
            Err(
                "f.xml: no device matches `BK1120@0x00130000`; the file holds \
                 BK1120 (product code 0x04602C22, revision 0x00100000), \
                 BK1120 (product code 0x04602C22, revision 0x00120000), \
                 BK1120 (product code 0x04602C22, revision 0x00110000)"
                    .to_string()
            )
        );
        assert_eq!(
            pick("0x04622C52"),
            Err("f.xml: `0x04622C52` matches different devices: \
                 EK1122 (product code 0x04622C52, revision 0x00000001), \
                 EK1122-0008 (product code 0x04622C52, revision 0x00000001); \
                 choose one by type name, or add @REVISION"
                .to_string())
        );
        assert_eq!(pick("EK1122-0008"), Ok(("EK1122-0008".to_string(), 1)));
        let only_demo = vec![dev("", "Demo", 0, 0)];
        assert_eq!(
            select(Path::new("g.eds"), only_demo, "EL1008")
                .map_err(|e| e.to_string())
                .unwrap_err(),
            "g.eds: no device matches `EL1008`; the file holds Demo (product code 0x00000000, \
             revision 0x00000000)"
        );
    }

    #[test]
    fn a_product_code_shared_by_different_names_and_revisions_is_refused() {
        let devices = vec![dev("A", "", 7, 1), dev("B", "", 7, 2)];
        let e = select(Path::new("f"), devices.clone(), "7").unwrap_err();
        assert_eq!(
            e.to_string(),
            "f: `7` matches different devices: A (product code 0x00000007, revision 0x00000001), \
             B (product code 0x00000007, revision 0x00000002); choose one by type name, or add \
             @REVISION"
        );
        let b = select(Path::new("f"), devices, "7@2").unwrap();
        assert_eq!(device_name(&b), "B");
    }
}
