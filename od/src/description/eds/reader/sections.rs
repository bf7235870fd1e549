//! The description from the named sections of an EDS/DCF: `[FileInfo]`, `[DeviceInfo]`,
//! `[DummyUsage]`, `[Comments]`, `[DeviceComissioning]` and the object lists.

use super::hex_u16;
use std::collections::BTreeMap;

use super::{strip_prefix_ignore_case, Builder, Entry, Kind, Section};
use crate::device::{CanInfo, Commissioning, DeviceDescription, FileInfo, Identity};
use crate::error::ParseError;
use crate::value::parse_integer;

impl<'i, 'a> Builder<'i, 'a> {
    pub(super) fn build(&self) -> Result<DeviceDescription, ParseError> {
        let mut desc = DeviceDescription::default();
        if let Some(section) = self.named(Kind::FileInfo) {
            desc.file_info = self.file_info(section)?;
        }
        let mut can = None;
        if let Some(section) = self.named(Kind::DeviceInfo) {
            let (identity, info) = self.device_info(section)?;
            desc.identity = identity;
            can = info;
        }
        if let Some(section) = self.named(Kind::DummyUsage) {
            can.get_or_insert_with(CanInfo::default).dummy_usage = self.dummy_usage(section)?;
        }
        desc.can = can;
        if let Some(section) = self.named(Kind::Comments) {
            desc.comments = self.comments(section)?;
        }
        if let Some(section) = self.named(Kind::Commissioning) {
            desc.commissioning = Some(self.commissioning(section)?);
        }
        let mut listed: BTreeMap<u16, &str> = BTreeMap::new();
        let mut lists = 0;
        for kind in [
            Kind::MandatoryObjects,
            Kind::OptionalObjects,
            Kind::ManufacturerObjects,
        ] {
            if let Some(section) = self.named(kind) {
                lists += 1;
                self.check_list(section, &mut listed)?;
            }
        }
        if lists > 0 {
            // Lely reads the objects its lists name and no others: one warning, at the first of them.
            let unlisted: Vec<&str> = self
                .objects
                .iter()
                .filter(|(index, _)| !listed.contains_key(index))
                .filter_map(|(_, sections)| sections.main.and_then(|i| self.section(i)))
                .map(|main| main.name)
                .collect();
            if let Some(first) = unlisted.first() {
                let mut names: Vec<String> =
                    unlisted.iter().take(8).map(|n| format!("[{n}]")).collect();
                if unlisted.len() > 8 {
                    names.push("…".into());
                }
                self.warn(
                    first,
                    format!(
                        "{} object(s) in none of the object lists, which Lely leaves out: {}",
                        unlisted.len(),
                        names.join(", ")
                    ),
                );
            }
        }
        let node_id = desc.node_id();
        for (&index, sections) in &self.objects {
            let Some(main) = sections.main.and_then(|i| self.section(i)) else {
                if let Some(sub) = sections.subs.values().next().and_then(|&i| self.section(i)) {
                    return Err(self.ini.error(
                        sub.name,
                        format!(
                            "section [{}] has no object section [{index:04X}] before or after it",
                            sub.name
                        ),
                    ));
                }
                // `[xxxxName]` / `[xxxxValue]` of an object the file does not describe: nothing to apply
                // them to.
                continue;
            };
            desc.dictionary
                .insert(self.object(index, main, sections, node_id)?);
        }
        Ok(desc)
    }

    fn file_info(&self, section: &Section<'a>) -> Result<FileInfo, ParseError> {
        let f = self.fields(
            section,
            [
                "FileName",
                "FileVersion",
                "FileRevision",
                "EDSVersion",
                "Description",
                "CreationTime",
                "CreationDate",
                "CreatedBy",
                "ModificationTime",
                "ModificationDate",
                "ModifiedBy",
            ],
        )?;
        let text = |i: usize| f[i].map_or_else(String::new, |e| e.value.to_string());
        Ok(FileInfo {
            file_name: text(0),
            file_version: text(1),
            file_revision: text(2),
            format_version: text(3),
            description: text(4),
            creation_time: text(5),
            creation_date: text(6),
            created_by: text(7),
            modification_time: text(8),
            modification_date: text(9),
            modified_by: text(10),
        })
    }

    /// The identity of `[DeviceInfo]`, and its CAN capabilities where it gives any of their keys.
    fn device_info(
        &self,
        section: &Section<'a>,
    ) -> Result<(Identity, Option<CanInfo>), ParseError> {
        const U32: &str = "a 32-bit number like 0x0000012A";
        let [vendor_name, vendor_number, product_name, product_number, revision, order_code] = self
            .fields(
                section,
                [
                    "VendorName",
                    "VendorNumber",
                    "ProductName",
                    "ProductNumber",
                    "RevisionNumber",
                    "OrderCode",
                ],
            )?;
        let text = |e: Option<&Entry<'a>>| e.map_or_else(String::new, |e| e.value.to_string());
        let identity = Identity {
            vendor_id: self.number(section, vendor_number, U32, 0)?,
            vendor_name: text(vendor_name),
            product_code: self.number(section, product_number, U32, 0)?,
            revision: self.number(section, revision, U32, 0)?,
            product_name: text(product_name),
            order_code: text(order_code),
            // An EDS has no key for them (CiA 306 `[DeviceInfo]`).
            hardware_version: String::new(),
            software_version: String::new(),
            firmware_version: String::new(),
        };

        const RATES: [u32; 8] = [10, 20, 50, 125, 250, 500, 800, 1000];
        let rate_keys = self.fields(
            section,
            [
                "BaudRate_10",
                "BaudRate_20",
                "BaudRate_50",
                "BaudRate_125",
                "BaudRate_250",
                "BaudRate_500",
                "BaudRate_800",
                "BaudRate_1000",
            ],
        )?;
        let any_rate = rate_keys.iter().any(Option::is_some);
        let mut baud_rates = Vec::new();
        for (rate, entry) in RATES.into_iter().zip(rate_keys) {
            if self.flag(section, entry, false)? {
                baud_rates.push(rate);
            }
        }

        let [master, slave, granularity, dynamic, group, rx, tx, lss] = self.fields(
            section,
            [
                "SimpleBootUpMaster",
                "SimpleBootUpSlave",
                "Granularity",
                "DynamicChannelsSupported",
                "GroupMessaging",
                "NrOfRXPDO",
                "NrOfTXPDO",
                "LSS_Supported",
            ],
        )?;
        let given = any_rate
            || [master, slave, granularity, dynamic, group, rx, tx, lss]
                .iter()
                .any(Option::is_some);
        let defaults = CanInfo::default();
        let info = CanInfo {
            baud_rates,
            simple_boot_up_master: self.flag(section, master, defaults.simple_boot_up_master)?,
            simple_boot_up_slave: self.flag(section, slave, defaults.simple_boot_up_slave)?,
            granularity: self.number(
                section,
                granularity,
                "a granularity in bits, 0 to 64",
                defaults.granularity,
            )?,
            dynamic_channels: self.number(
                section,
                dynamic,
                "a number of dynamic channels, 0 to 255",
                defaults.dynamic_channels,
            )?,
            group_messaging: self.flag(section, group, defaults.group_messaging)?,
            nr_of_rx_pdo: self.number(
                section,
                rx,
                "a number of RPDOs, 0 to 512",
                defaults.nr_of_rx_pdo,
            )?,
            nr_of_tx_pdo: self.number(
                section,
                tx,
                "a number of TPDOs, 0 to 512",
                defaults.nr_of_tx_pdo,
            )?,
            lss_supported: self.flag(section, lss, defaults.lss_supported)?,
            dummy_usage: Vec::new(),
        };
        Ok((identity, given.then_some(info)))
    }

    /// `DummyXXXX=1`: the data types (by index) that may be mapped as dummies.
    fn dummy_usage(&self, section: &Section<'a>) -> Result<Vec<u16>, ParseError> {
        let mut usable = Vec::new();
        for entry in self.ini.entries(section) {
            let Some(index) = strip_prefix_ignore_case(entry.key, "Dummy").and_then(hex_u16) else {
                continue;
            };
            if self.flag(section, Some(entry), false)? {
                usable.push(index);
            }
        }
        usable.sort_unstable();
        usable.dedup();
        Ok(usable)
    }

    fn comments(&self, section: &Section<'a>) -> Result<Vec<String>, ParseError> {
        let [lines] = self.fields(section, ["Lines"])?;
        let count: u32 = self.number(section, lines, "a number of comment lines", 0)?;
        let numbered = self.numbered(section, "Line")?;
        (1..=count)
            .map(|n| {
                // Free text: a `;` in a comment line is part of it.
                numbered
                    .get(&n)
                    .map(|e| e.whole.to_string())
                    .ok_or_else(|| {
                        self.missing(
                            section,
                            &format!("Line{n}"),
                            &format!("Lines={count} announces it"),
                        )
                    })
            })
            .collect()
    }

    fn commissioning(&self, section: &Section<'a>) -> Result<Commissioning, ParseError> {
        let [node_id, node_name, baud_rate, net_number, network_name, manager, serial] = self
            .fields(
                section,
                [
                    "NodeID",
                    "NodeName",
                    "Baudrate",
                    "NetNumber",
                    "NetworkName",
                    "CANopenManager",
                    "LSS_SerialNumber",
                ],
            )?;
        // Lely's DCFs of a node that LSS is yet to configure say `NodeID=0xFF`, or give none; Lely reads
        // both as unconfigured, and python-canopen takes whatever number is there. A number that is no
        // node-ID leaves the node unconfigured, with a warning.
        let node_id = match node_id.filter(|e| !e.value.is_empty()) {
            Some(e) => {
                let id = parse_integer(e.value)
                    .ok_or_else(|| self.bad(section, e, "a node-ID, 1 to 127"))?;
                match u8::try_from(id).ok().filter(|id| (1..=127).contains(id)) {
                    Some(id) => Some(id),
                    None => {
                        let what = if id == 0xFF {
                            "marks a node that LSS has yet to configure"
                        } else {
                            "is no node-ID (1 to 127)"
                        };
                        self.warn(
                            e.value,
                            format!(
                                "NodeID= in [{}]: `{}` {what}; the node is unconfigured, and `$NODEID` values stay relative to the node-ID",
                                section.name, e.value
                            ),
                        );
                        None
                    }
                }
            }
            None => {
                self.warn(
                    section.name,
                    format!(
                        "[{}] has no NodeID=; the node is unconfigured, and `$NODEID` values stay relative to the node-ID",
                        section.name
                    ),
                );
                None
            }
        };
        let text = |e: Option<&Entry<'a>>| e.map_or_else(String::new, |e| e.value.to_string());
        Ok(Commissioning {
            node_id,
            node_name: text(node_name),
            baud_rate: self.number(section, baud_rate, "a bit rate in kbit/s", 0)?,
            net_number: self.number(section, net_number, "a 32-bit network number", 0)?,
            network_name: text(network_name),
            canopen_manager: self.flag(section, manager, false)?,
            lss_serial_number: self.number(section, serial, "a 32-bit serial number", 0)?,
        })
    }

    /// Checks an object list: `SupportedObjects=` is a number and every entry is an object index, and
    /// adds the objects it lists to `listed` (index → the list naming it). A count that is not the number of
    /// entries, an object listed twice and a listed object without its section are warnings: python-canopen
    /// reads the sections whatever the lists say, Lely reads the lists' first `SupportedObjects` entries and
    /// refuses an object without its section.
    fn check_list(
        &self,
        section: &Section<'a>,
        listed: &mut BTreeMap<u16, &'a str>,
    ) -> Result<(), ParseError> {
        let [supported] = self.fields(section, ["SupportedObjects"])?;
        let count = self.number::<u32>(section, supported, "a number of objects", 0)?;
        let entries = self.numbered(section, "")?;
        if let Some(s) = supported {
            if usize::try_from(count).ok() != Some(entries.len()) {
                self.warn(
                    s.value,
                    format!(
                        "SupportedObjects={} in [{}], but it lists {} object(s)",
                        s.value.trim(),
                        section.name,
                        entries.len()
                    ),
                );
            }
        }
        for entry in entries.values() {
            const INDEX: &str = "an object index like 0x1000";
            if entry.value.is_empty() {
                return Err(self.bad(section, entry, INDEX));
            }
            // A listed object without its section is skipped: CiA 306 wants one, but real files
            // (python-canopen's e35.eds) list objects they do not describe, and every other tool reads them.
            let index = self.number::<u16>(section, Some(entry), INDEX, 0)?;
            if let Some(first) = listed.insert(index, section.name) {
                self.warn(
                    entry.value,
                    format!(
                        "[{}] lists 0x{index:04X} again (first in [{first}])",
                        section.name
                    ),
                );
            } else if self.objects.get(&index).is_none_or(|s| s.main.is_none()) {
                self.warn(
                    entry.value,
                    format!(
                        "[{}] lists 0x{index:04X}, which has no section [{index:04X}] (Lely refuses that)",
                        section.name
                    ),
                );
            }
        }
        Ok(())
    }
}
