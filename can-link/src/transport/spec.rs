//! The bus notation: `socketcan:IFACE` (or the bare `IFACE`, as candump and python-can users write
//! it), `socketcand://HOST:PORT/CHANNEL`, `socketcand-listen:ADDR:PORT`. Every tool takes its default
//! bus from [`BUS_VARIABLE`] when `--bus` is not given.

use std::fmt;
use std::net::SocketAddr;
use std::str::FromStr;

/// The environment variable every tool reads its bus from when `--bus` is not given, in the same
/// notation (`CANOPEN_BUS=can0`, `CANOPEN_BUS=socketcand://10.0.0.2:29536/can1`).
pub const BUS_VARIABLE: &str = "CANOPEN_BUS";

/// socketcand's usual TCP port.
pub const SOCKETCAND_DEFAULT_PORT: u16 = 29536;

/// Which bus to use, as written on a command line.
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum BusSpec {
    /// A SocketCAN interface: `socketcan:vcan0`.
    SocketCan {
        /// Interface name.
        iface: String,
    },
    /// A socketcand daemon to connect to: `socketcand://127.0.0.1:29536/can0` (port defaults to 29536,
    /// channel to `can0`).
    Socketcand {
        /// Host name or address.
        host: String,
        /// TCP port.
        port: u16,
        /// The channel opened with `< open CHANNEL >`.
        channel: String,
    },
    /// Be a socketcand server: `socketcand-listen:127.0.0.1:29536`.
    SocketcandListen {
        /// Address to bind.
        addr: SocketAddr,
    },
}

/// Why a bus notation was refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("bad bus {text:?}: {reason} (expected IFACE or socketcan:IFACE, socketcand://HOST:PORT/CHANNEL or socketcand-listen:ADDR:PORT)")]
pub struct SpecError {
    /// The text given.
    pub text: String,
    /// What was wrong.
    pub reason: String,
}

impl FromStr for BusSpec {
    type Err = SpecError;

    fn from_str(text: &str) -> Result<BusSpec, SpecError> {
        let err = |reason: &str| SpecError {
            text: text.to_string(),
            reason: reason.to_string(),
        };
        let iface = |iface: &str| {
            // Linux interface names: 1–15 bytes, no '/', no whitespace.
            if iface.is_empty() || iface.len() > 15 {
                return Err(err("the interface name must be 1 to 15 characters"));
            }
            if iface.contains(['/', ':']) || iface.chars().any(char::is_whitespace) {
                return Err(err("the interface name holds '/', ':' or a space"));
            }
            Ok(BusSpec::SocketCan {
                iface: iface.to_string(),
            })
        };
        if let Some(name) = text.strip_prefix("socketcan:") {
            return iface(name);
        }
        // A bare interface name (`can0`, `vcan0`, `slcan0`): what candump and python-can take.
        if !text.is_empty()
            && text
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.' | '@'))
            && text.starts_with(|c: char| c.is_ascii_alphabetic())
        {
            return iface(text);
        }
        if let Some(rest) = text.strip_prefix("socketcand://") {
            let (authority, channel) = match rest.split_once('/') {
                Some((a, c)) => (a, c),
                None => (rest, "can0"),
            };
            let channel = if channel.is_empty() { "can0" } else { channel };
            if channel.contains(['/', ' ', '<', '>']) {
                return Err(err("the channel name holds '/', ' ', '<' or '>'"));
            }
            let (host, port) = split_host_port(authority).map_err(|r| err(&r))?;
            return Ok(BusSpec::Socketcand {
                host,
                port: port.unwrap_or(SOCKETCAND_DEFAULT_PORT),
                channel: channel.to_string(),
            });
        }
        if let Some(rest) = text.strip_prefix("socketcand-listen:") {
            let addr = rest
                .parse::<SocketAddr>()
                .map_err(|_| err("the listen address must be ADDR:PORT, e.g. 127.0.0.1:29536"))?;
            return Ok(BusSpec::SocketcandListen { addr });
        }
        Err(err("unknown kind of bus"))
    }
}

fn split_host_port(authority: &str) -> Result<(String, Option<u16>), String> {
    if authority.is_empty() {
        return Err("the host is missing".into());
    }
    // [v6]:port
    if let Some(rest) = authority.strip_prefix('[') {
        let (host, after) = rest
            .split_once(']')
            .ok_or_else(|| "an IPv6 address needs its closing ']'".to_string())?;
        let port = match after.strip_prefix(':') {
            Some(p) => Some(parse_port(p)?),
            None if after.is_empty() => None,
            None => return Err("unexpected text after the IPv6 address".into()),
        };
        return Ok((host.to_string(), port));
    }
    match authority.rsplit_once(':') {
        Some((host, port)) if !host.is_empty() => Ok((host.to_string(), Some(parse_port(port)?))),
        Some(_) => Err("the host is missing".into()),
        None => Ok((authority.to_string(), None)),
    }
}

fn parse_port(text: &str) -> Result<u16, String> {
    match text.parse::<u16>() {
        Ok(p) if p > 0 => Ok(p),
        _ => Err(format!("port {text:?} is not 1 to 65535")),
    }
}

impl BusSpec {
    /// The bus's name as a capture names its interface (pcapng's `if_name`): the interface of
    /// SocketCAN (`vcan0`), `socketcand:HOST:PORT/CHANNEL` for a daemon's channel,
    /// `socketcand-listen:ADDR:PORT` for the server.
    pub fn interface_name(&self) -> String {
        match self {
            BusSpec::SocketCan { iface } => iface.clone(),
            BusSpec::Socketcand {
                host,
                port,
                channel,
            } if host.contains(':') => format!("socketcand:[{host}]:{port}/{channel}"),
            BusSpec::Socketcand {
                host,
                port,
                channel,
            } => format!("socketcand:{host}:{port}/{channel}"),
            BusSpec::SocketcandListen { addr } => format!("socketcand-listen:{addr}"),
        }
    }
}

impl fmt::Display for BusSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BusSpec::SocketCan { iface } => write!(f, "socketcan:{iface}"),
            BusSpec::Socketcand {
                host,
                port,
                channel,
            } if host.contains(':') => write!(f, "socketcand://[{host}]:{port}/{channel}"),
            BusSpec::Socketcand {
                host,
                port,
                channel,
            } => write!(f, "socketcand://{host}:{port}/{channel}"),
            BusSpec::SocketcandListen { addr } => write!(f, "socketcand-listen:{addr}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A bare interface name is SocketCAN, as candump and python-can take it.
    #[test]
    fn a_bare_interface_name_is_socketcan() {
        for name in ["can0", "vcan0", "slcan0", "can_fd-1", "vxcan0.1"] {
            assert_eq!(
                name.parse::<BusSpec>().unwrap(),
                BusSpec::SocketCan { iface: name.into() },
                "{name}"
            );
        }
    }

    #[test]
    fn parses_each_kind() {
        assert_eq!(
            "socketcan:vcan0".parse::<BusSpec>().unwrap(),
            BusSpec::SocketCan {
                iface: "vcan0".into()
            }
        );
        assert_eq!(
            "socketcand://127.0.0.1:29536/can1"
                .parse::<BusSpec>()
                .unwrap(),
            BusSpec::Socketcand {
                host: "127.0.0.1".into(),
                port: 29536,
                channel: "can1".into()
            }
        );
        assert_eq!(
            "socketcand://localhost".parse::<BusSpec>().unwrap(),
            BusSpec::Socketcand {
                host: "localhost".into(),
                port: SOCKETCAND_DEFAULT_PORT,
                channel: "can0".into()
            }
        );
        assert_eq!(
            "socketcand://[::1]:4000/vcan0"
                .parse::<BusSpec>()
                .unwrap()
                .to_string(),
            "socketcand://[::1]:4000/vcan0"
        );
        assert_eq!(
            "socketcand-listen:0.0.0.0:29536"
                .parse::<BusSpec>()
                .unwrap(),
            BusSpec::SocketcandListen {
                addr: "0.0.0.0:29536".parse().unwrap()
            }
        );
    }

    /// The names a capture gives each kind of bus.
    #[test]
    fn interface_names() {
        for (text, name) in [
            ("vcan0", "vcan0"),
            ("socketcan:can1", "can1"),
            (
                "socketcand://127.0.0.1:29536/can0",
                "socketcand:127.0.0.1:29536/can0",
            ),
            (
                "socketcand://[::1]:4000/vcan0",
                "socketcand:[::1]:4000/vcan0",
            ),
            (
                "socketcand-listen:127.0.0.1:4000",
                "socketcand-listen:127.0.0.1:4000",
            ),
        ] {
            assert_eq!(text.parse::<BusSpec>().unwrap().interface_name(), name);
        }
    }

    #[test]
    fn refuses_bad_notation_with_the_reason() {
        for (text, reason) in [
            ("tcp://host", "unknown kind"),
            ("0can", "unknown kind"),
            ("", "unknown kind"),
            ("averyveryverylongname", "1 to 15"),
            ("socketcan:", "1 to 15"),
            ("socketcan:averyveryverylongname", "1 to 15"),
            ("socketcand://:29536/can0", "host is missing"),
            ("socketcand://host:0/can0", "not 1 to 65535"),
            ("socketcand://host:99999/can0", "not 1 to 65535"),
            ("socketcand-listen:localhost", "ADDR:PORT"),
        ] {
            let e = text.parse::<BusSpec>().unwrap_err();
            assert!(e.to_string().contains(reason), "{text}: {e}");
        }
    }
}
