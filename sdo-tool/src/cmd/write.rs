//! `write NODE OBJECT [TYPE] VALUE`: one entry written, the value checked against the description
//! first when there is one.

use std::io::Write;

use super::{emit, Context};
use crate::{SdoCommands, ToolError, UsageError};

/// `write`'s arguments.
#[derive(Debug, clap::Args)]
pub struct WriteArgs {
    /// Node-ID, 1–127 (with --ethercat: the slave's position, 1 = first).
    pub node: u8,
    /// The object.
    pub object: String,
    /// TYPE VALUE, or VALUE alone with --od.
    #[arg(num_args = 1..=2, required = true, allow_hyphen_values = true, value_name = "[TYPE] VALUE")]
    pub rest: Vec<String>,
}

/// `write` on `commands` (any network), printing to `out`.
pub fn run(
    args: &WriteArgs,
    commands: &mut SdoCommands<'_>,
    ctx: Context<'_>,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    let WriteArgs { node, object, rest } = args;
    let (ty, value) = match rest.as_slice() {
        [v] => (None, v.as_str()),
        [t, v] => (Some(t.as_str()), v.as_str()),
        _ => return Err(UsageError::WriteArguments.into()),
    };
    // A type alone is a value left out, unless the entry is a string it could be.
    if let (None, Some(t)) = (ty, crate::TypeCode::parse(value)) {
        let addr = commands.object(object)?;
        let textual = commands
            .od
            .and_then(|d| d.entry(addr.index, addr.sub).ok())
            .is_some_and(|e| {
                matches!(
                    e.data_type,
                    od::DataType::VisibleString
                        | od::DataType::UnicodeString
                        | od::DataType::OctetString
                        | od::DataType::Domain
                )
            });
        if !textual {
            return Err(UsageError::ValueMissing {
                address: addr,
                text: value.to_string(),
                data_type: t.data_type,
            }
            .into());
        }
    }
    commands.write(*node, object, ty, value)?;
    emit(out, ctx.json, "OK", serde_json::json!({"ok": true}))
}
