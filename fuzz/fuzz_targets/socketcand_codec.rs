#![no_main]
//! Arbitrary bytes into the socketcand element splitter and parsers: no panic, the bytes held stay
//! within one element, every element parses or is refused, and every error answer is printable
//! ASCII with no bracket inside.

use socketcan_node::transport::socketcand::codec::{Command, Message, Splitter, MAX_ELEMENT};

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let mut s = Splitter::new();
    // Fed in pieces, as reads arrive.
    for piece in data.chunks(7) {
        s.push(piece);
        while let Some(element) = s.next_element() {
            let text = match element {
                Ok(e) => {
                    let _ = Message::parse(&e);
                    match Command::parse(&e) {
                        Ok(c) => {
                            let again = c.emit();
                            assert!(again.starts_with('<') && again.ends_with('>'));
                            continue;
                        }
                        Err(err) => err.to_string(),
                    }
                }
                Err(err) => err.to_string(),
            };
            let answer = Message::Error(text).emit();
            assert!(answer.is_ascii(), "{answer}");
            let inner = &answer[1..answer.len() - 1];
            assert!(!inner.contains('<') && !inner.contains('>'), "{answer}");
        }
        assert!(
            s.pending() <= MAX_ELEMENT + piece.len(),
            "{} bytes held",
            s.pending()
        );
    }
});
