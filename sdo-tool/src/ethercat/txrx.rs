//! ethercrab's TX/RX task on this project's raw socket ([`RawSocket`] of `ecat-link`) instead of
//! ethercrab's own, so that its frames can be captured ([`RawSocket::capture_to`]): each frame
//! ethercrab has ready is sent ([`PduTx::next_sendable_frame`]), each frame waiting on the socket is
//! handed to ethercrab ([`PduRx::receive_frame`]), and the task waits for the socket with the
//! executor (`async_io`) until either has more to do.
//!
//! It ends as ethercrab's own task ends: with the PDUs handed back when the main device asks it to
//! exit, with [`Error::SendFrame`] when a frame cannot be sent, with [`Error::ReceiveFrame`] at the
//! first frame ethercrab cannot place (one of another master, an answer after its timeout).

use std::future::Future;
use std::pin::Pin;
use std::task::{Context, Poll};

use async_io::Async;
use ethercrab::error::Error;
use ethercrab::{PduRx, PduTx};

use crate::link::RawSocket;

/// The longest frame taken from the socket (a jumbo frame; an EtherCAT frame is at most 1,514
/// bytes).
const FRAME: usize = 9216;

/// The TX/RX task: a future that ends only with an error or when ethercrab asks it to.
pub struct TxRx<'sto> {
    socket: Async<RawSocket>,
    tx: Option<PduTx<'sto>>,
    rx: Option<PduRx<'sto>>,
    buf: Vec<u8>,
}

impl<'sto> TxRx<'sto> {
    /// The task over `socket` (opened on the chain's interface) with ethercrab's two ends.
    pub fn new(socket: RawSocket, tx: PduTx<'sto>, rx: PduRx<'sto>) -> std::io::Result<TxRx<'sto>> {
        Ok(TxRx {
            socket: Async::new(socket)?,
            tx: Some(tx),
            rx: Some(rx),
            buf: vec![0; FRAME],
        })
    }
}

impl<'sto> Future for TxRx<'sto> {
    type Output = Result<(PduTx<'sto>, PduRx<'sto>), Error>;

    fn poll(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<Self::Output> {
        let this = &mut *self;
        let (Some(tx), Some(rx)) = (this.tx.as_mut(), this.rx.as_mut()) else {
            // Polled again after it ended.
            return Poll::Ready(Err(Error::Internal));
        };
        // Woken when ethercrab has a frame to send.
        tx.replace_waker(cx.waker());
        if tx.should_exit() {
            let (tx, rx) = (this.tx.take(), this.rx.take());
            return match (tx, rx) {
                (Some(tx), Some(rx)) => Poll::Ready(Ok((tx.release(), rx.release()))),
                _ => Poll::Ready(Err(Error::Internal)),
            };
        }
        let socket = this.socket.get_ref();
        while let Some(frame) = tx.next_sendable_frame() {
            let sent = frame.send_blocking(|data| {
                socket
                    .send(data)
                    .map(|()| data.len())
                    .map_err(|_| Error::SendFrame)
            });
            if let Err(e) = sent {
                return Poll::Ready(Err(e));
            }
        }
        loop {
            match socket.recv(&mut this.buf) {
                Ok(Some(n)) => {
                    if rx.receive_frame(&this.buf[..n]).is_err() {
                        return Poll::Ready(Err(Error::ReceiveFrame));
                    }
                }
                // Nothing waiting: woken when a frame is (the capture written before the wait).
                Ok(None) => match this.socket.poll_readable(cx) {
                    Poll::Ready(Ok(())) => {}
                    Poll::Ready(Err(_)) => return Poll::Ready(Err(Error::ReceiveFrame)),
                    Poll::Pending => {
                        socket.flush_capture();
                        return Poll::Pending;
                    }
                },
                Err(_) => return Poll::Ready(Err(Error::ReceiveFrame)),
            }
        }
    }
}
