//! `read NODE OBJECT [TYPE]`: one entry's value, with its unit and named bits; with a description
//! and a RECORD or ARRAY named as a whole, each readable entry of it.

use std::io::Write;

use od::dict::Address;

use super::{emit, Context};
use crate::{SdoCommands, ToolError};

/// `read`'s arguments.
#[derive(Debug, clap::Args)]
pub struct ReadArgs {
    /// Node-ID, 1–127 (with --ethercat: the slave's position, 1 = first).
    pub node: u8,
    /// The object.
    pub object: String,
    /// The type (may be left out with --od).
    #[arg(value_name = "TYPE")]
    pub ty: Option<String>,
    /// Show a long value (a DOMAIN's, an OCTET_STRING's) whole, not its first 32 bytes and its
    /// length.
    #[arg(long)]
    pub full: bool,
}

/// `read` on `commands` (any network), printing to `out`.
pub fn run(
    args: &ReadArgs,
    commands: &mut SdoCommands<'_>,
    ctx: Context<'_>,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    let ReadArgs {
        node,
        object,
        ty,
        full,
    } = args;
    if let (Some(d), None) = (ctx.desc, ty) {
        if let Some(index) = whole_object(&d.dictionary, object) {
            let whole = Whole {
                dict: &d.dictionary,
                index,
                json: ctx.json,
                full: *full,
            };
            return read_object(commands, *node, whole, out);
        }
    }
    let (value, text) = commands.read_typed(*node, object, ty.as_deref())?;
    let addr = commands.object(object)?;
    let read_as = ty
        .as_deref()
        .and_then(crate::TypeCode::parse)
        .map(|c| c.data_type);
    let meaning = Meaning::of(commands.od, addr, &value, read_as);
    let mut v = serde_json::json!({
        "node": node,
        "object": addr.to_string(),
        "value": json_value(&value),
        "text": text,
    });
    meaning.add_to(&mut v);
    let shown = crate::show::elided(&value, text, *full);
    emit(out, ctx.json, meaning.show(&shown), v)
}

/// A value as JSON: numbers as numbers, a string as its text, bytes as hex (`"01 02 0A"`), a time
/// as its milliseconds and days.
pub fn json_value(v: &od::value::Value) -> serde_json::Value {
    use od::value::Value;
    match v {
        Value::Bool(b) => (*b).into(),
        Value::Int(i) => (*i).into(),
        Value::Uint(u) => (*u).into(),
        Value::Real32(f) => {
            serde_json::Number::from_f64(f64::from(*f)).map_or(serde_json::Value::Null, Into::into)
        }
        Value::Real64(f) => {
            serde_json::Number::from_f64(*f).map_or(serde_json::Value::Null, Into::into)
        }
        Value::String(t) => t.clone().into(),
        Value::Unicode(u) => String::from_utf16_lossy(u).into(),
        Value::Bytes(b) => b
            .iter()
            .map(|x| format!("{x:02X}"))
            .collect::<Vec<_>>()
            .join(" ")
            .into(),
        Value::Time(t) => serde_json::json!({"ms": t.ms, "days": t.days}),
    }
}

/// What a read value means beyond its number: its unit (from the description) and the names of
/// the bits set in it (those the description lists, or CiA 402's for its controlword and
/// statusword).
#[derive(Debug, Default, PartialEq)]
pub struct Meaning {
    /// The unit's symbol.
    pub unit: Option<String>,
    /// The names of the set bits, lowest bit first; `None` when the entry has no named bits.
    pub bits: Option<Vec<String>>,
}

impl Meaning {
    /// The meaning of `value` read from `addr` as `read_as` (the type given, else the
    /// description's), with `dict` for its description.
    pub fn of(
        dict: Option<&od::Dictionary>,
        addr: Address,
        value: &od::value::Value,
        read_as: Option<od::DataType>,
    ) -> Meaning {
        use od::value::Value;
        let object = dict.and_then(|d| d.object(addr.index));
        let entry = object.and_then(|o| o.subs.get(&addr.sub));
        let unit = entry
            .and_then(|e| e.unit)
            .map(od::units::unit_text)
            .filter(|u| !u.is_empty());
        let number = match value {
            Value::Uint(u) => Some(*u),
            Value::Int(i) => Some(*i as u64),
            _ => None,
        };
        let bits = number.and_then(|n| {
            let size = read_as.or(entry.map(|e| e.data_type))?.bit_size()?;
            let description = dict.and_then(|d| crate::show::bit_description(d, addr));
            let named = od::bits::bit_names(addr.index, addr.sub, description, size);
            (!named.is_empty()).then(|| od::bits::set_names(n, &named))
        });
        Meaning { unit, bits }
    }

    /// `text` with the unit after it and the set bits in brackets: `50000 mV`,
    /// `17416  [Stopped Position_Invalid Module_OK]`.
    pub fn show(&self, text: &str) -> String {
        let mut t = text.to_string();
        if let Some(u) = &self.unit {
            t.push(' ');
            t.push_str(u);
        }
        if let Some(bits) = &self.bits {
            t.push_str(&format!("  [{}]", bits.join(" ")));
        }
        t
    }

    /// Adds `unit` and `bits` to a JSON object where there are any.
    pub fn add_to(&self, v: &mut serde_json::Value) {
        if let Some(u) = &self.unit {
            v["unit"] = u.clone().into();
        }
        if let Some(bits) = &self.bits {
            v["bits"] = bits.clone().into();
        }
    }
}

/// The index of the RECORD or ARRAY `text` names as a whole (its name, or its index without a
/// sub-index, `0x1018`), for `read` to read every entry of it.
fn whole_object(dict: &od::Dictionary, text: &str) -> Option<u16> {
    let t = text.trim();
    if t.contains(':') || t.contains('.') {
        return None;
    }
    let index = match t
        .strip_prefix("0x")
        .or_else(|| t.strip_prefix("0X"))
        .map(|h| u16::from_str_radix(h, 16))
    {
        Some(Ok(i)) => i,
        Some(Err(_)) => return None,
        None => {
            dict.objects()
                .find(|o| o.kind.has_subs() && o.name.eq_ignore_ascii_case(t))?
                .index
        }
    };
    dict.object(index)
        .filter(|o| o.kind.has_subs())
        .map(|o| o.index)
}

/// A whole RECORD or ARRAY to read: its index in `dict`, and how its entries are shown.
struct Whole<'a> {
    dict: &'a od::Dictionary,
    index: u16,
    json: bool,
    full: bool,
}

/// `read` of a whole RECORD or ARRAY: each readable entry of it, in sub-index order, a line each;
/// an entry the node refuses is said so and the others go on (exit 1 at the end).
fn read_object(
    commands: &mut SdoCommands<'_>,
    node: u8,
    whole: Whole<'_>,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    let Whole {
        dict,
        index,
        json,
        full,
    } = whole;
    let io = ToolError::Output;
    let object = dict.object(index).expect("whole_object found it");
    let mut entries = Vec::new();
    let mut refused = 0;
    for (&sub, e) in &object.subs {
        if !e.access.kind.readable() {
            continue;
        }
        let addr = Address::new(index, sub);
        // The type from the description (the commands have it).
        match commands.read_typed(node, &addr.to_string(), None) {
            Ok((value, text)) => {
                let meaning = Meaning::of(Some(dict), addr, &value, None);
                if !json {
                    let shown = crate::show::elided(&value, text.clone(), full);
                    writeln!(out, "{addr}  {} = {}", e.name, meaning.show(&shown)).map_err(io)?;
                }
                let mut v = serde_json::json!({
                    "object": addr.to_string(), "name": e.name,
                    "value": json_value(&value), "text": text,
                });
                meaning.add_to(&mut v);
                entries.push(v);
            }
            Err(err @ ToolError::Abort { .. }) => {
                refused += 1;
                if !json {
                    writeln!(out, "{addr}  {}: {err}", e.name).map_err(io)?;
                }
                entries.push(serde_json::json!({
                    "object": addr.to_string(), "name": e.name, "error": err.to_string(),
                }));
            }
            Err(err) => return Err(err),
        }
    }
    if json {
        writeln!(
            out,
            "{}",
            serde_json::json!({"node": node, "object": format!("0x{index:04X}"), "entries": entries})
        )
        .map_err(io)?;
    }
    if refused > 0 {
        return Err(ToolError::Refused(refused));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::Meaning;
    use od::dict::Address;
    use od::object::{AccessType, Object, SubObject};
    use od::{DataType, Dictionary, Value};

    fn dict() -> Dictionary {
        let mut d = Dictionary::new();
        let mut threshold = SubObject::new("Threshold", DataType::Unsigned32, AccessType::Rw);
        threshold.unit = Some(0xFD26_0000);
        d.insert(Object::var(0x8000, threshold));
        d.insert(Object::var(
            0x2000,
            SubObject::new("Flags", DataType::Unsigned8, AccessType::Ro)
                .with_description("Bit 7 Ready; 1 Busy; 0 Error."),
        ));
        d.insert(Object::var(
            0x2001,
            SubObject::new("Signed", DataType::Integer8, AccessType::Ro)
                .with_description("Bit 7 Negative; 0 Odd"),
        ));
        // A VAR whose bit list is the object's description; a RECORD whose object description
        // lists bits that are not its entries'.
        let mut var = Object::var(
            0x2002,
            SubObject::new("Word", DataType::Unsigned16, AccessType::Ro),
        );
        var.description = Some("Bit 9 Nine".into());
        d.insert(var);
        let mut record = Object::structured(0x2003, "Rec", od::ObjectKind::Record).with_sub(
            1,
            SubObject::new("Entry", DataType::Unsigned16, AccessType::Ro),
        );
        record.description = Some("Bit 9 Nine".into());
        d.insert(record);
        d
    }

    /// A unit follows the value; the set bits of a word whose description lists them come in
    /// brackets, lowest first; CiA 402's statusword is known without a description.
    #[test]
    fn values_are_shown_with_their_unit_and_bits() {
        let d = dict();
        let m = Meaning::of(
            Some(&d),
            Address::new(0x8000, 0),
            &Value::Uint(50_000),
            None,
        );
        assert_eq!(m.unit.as_deref(), Some("mV"));
        assert_eq!(m.bits, None);
        assert_eq!(m.show("50000"), "50000 mV");
        let m = Meaning::of(Some(&d), Address::new(0x2000, 0), &Value::Uint(0x83), None);
        assert_eq!(
            m.bits,
            Some(vec!["Error".to_string(), "Busy".into(), "Ready".into()])
        );
        assert_eq!(m.show("131"), "131  [Error Busy Ready]");
        // No bit set: the brackets are empty, so that the word is seen to have named bits.
        let m = Meaning::of(Some(&d), Address::new(0x2000, 0), &Value::Uint(0), None);
        assert_eq!(m.show("0"), "0  []");
        // CiA 402 statusword 0x0637 read as u16 without a description: Operation enabled, Remote,
        // Target reached.
        let m = Meaning::of(
            None,
            Address::new(0x6041, 0),
            &Value::Uint(0x0637),
            Some(DataType::Unsigned16),
        );
        assert_eq!(
            m.bits.unwrap(),
            [
                "Ready_to_switch_on",
                "Switched_on",
                "Operation_enabled",
                "Voltage_enabled",
                "Quick_stop",
                "Remote",
                "Target_reached"
            ]
        );
        // Read as another size, or with no size known, it is not the statusword.
        let m = Meaning::of(
            None,
            Address::new(0x6041, 0),
            &Value::Uint(0x0637),
            Some(DataType::Unsigned32),
        );
        assert_eq!(m, Meaning::default());
        let m = Meaning::of(None, Address::new(0x6041, 0), &Value::Uint(0x0637), None);
        assert_eq!(m, Meaning::default());
        // A signed word: its two's complement bits (-127 is 0x81).
        let m = Meaning::of(Some(&d), Address::new(0x2001, 0), &Value::Int(-127), None);
        assert_eq!(m.bits, Some(vec!["Odd".to_string(), "Negative".into()]));
        // A VAR's object description lists its bits; a RECORD's does not list its entries'.
        let m = Meaning::of(Some(&d), Address::new(0x2002, 0), &Value::Uint(0x200), None);
        assert_eq!(m.bits, Some(vec!["Nine".to_string()]));
        let m = Meaning::of(Some(&d), Address::new(0x2003, 1), &Value::Uint(0x200), None);
        assert_eq!(m.bits, None);
        // A string has no bits.
        let m = Meaning::of(
            Some(&d),
            Address::new(0x2000, 0),
            &Value::String("x".into()),
            None,
        );
        assert_eq!(m.bits, None);
        let mut v = serde_json::json!({});
        Meaning::of(Some(&d), Address::new(0x8000, 0), &Value::Uint(1), None).add_to(&mut v);
        assert_eq!(v, serde_json::json!({"unit": "mV"}));
    }
}
