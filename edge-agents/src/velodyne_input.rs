//! `lidar --velodyne ADDR:PORT`: VLP-16 / VLP-32C data packets over UDP, one scan per rotation.
//!
//! A reader thread receives datagrams, decodes them (`frontends::lidar::decode_velodyne_packet`) and cuts
//! rotations (`RotationAssembler`: a scan ends when the block starting the next one arrives). A rotation is
//! stamped at the host time of its first packet less `--pipeline-delay-ms`. A datagram of the wrong size, with
//! a bad block flag or an unknown product id is counted and logged (at most every 5 s) and the reader goes on.
//! After `--idle-timeout-s` without a packet (once packets have come) the input ends and the agent withdraws
//! the sensor.

use std::net::{SocketAddr, ToSocketAddrs, UdpSocket};
use std::time::{Duration, Instant};

use frontends::lidar::{decode_velodyne_packet, RotationAssembler};
use transport::LogLimiter;

use crate::capture_clock::CaptureClock;
use crate::error::AgentError;
use crate::lidar_live::{Captured, ScanQueue};

/// The Velodyne's default data port.
pub const DEFAULT_PORT: u16 = 2368;
/// How long one receive waits before the idle timeout is checked.
const RECEIVE_POLL: Duration = Duration::from_millis(100);
/// At most one warning about malformed packets per this interval.
const MALFORMED_LOG_INTERVAL: Duration = Duration::from_secs(5);
/// Receive buffer: larger than any datagram, so an oversized one is seen as such rather than truncated to fit.
const BUFFER_LEN: usize = 2048;

/// Parses `ADDR` or `ADDR:PORT` (port 2368 when absent).
pub fn parse_address(text: &str) -> Result<SocketAddr, AgentError> {
    let bad = |reason: String| AgentError::invalid("--velodyne", reason);
    let with_port = if text.parse::<SocketAddr>().is_ok()
        || text
            .rsplit_once(':')
            .is_some_and(|(_, p)| p.parse::<u16>().is_ok())
    {
        text.to_owned()
    } else {
        format!("{text}:{DEFAULT_PORT}")
    };
    with_port
        .to_socket_addrs()
        .map_err(|e| bad(format!("{text}: {e}")))?
        .next()
        .ok_or_else(|| bad(format!("{text} names no address")))
}

/// Binds the socket (errors here stop the agent before anything is published) and starts the reader thread.
pub fn start(
    address: SocketAddr,
    idle_timeout_s: f64,
    clock: CaptureClock,
    queue: ScanQueue,
) -> Result<(), AgentError> {
    if !(idle_timeout_s.is_finite() && idle_timeout_s >= 0.0) {
        return Err(AgentError::invalid(
            "--idle-timeout-s",
            format!("{idle_timeout_s} is not a number of seconds >= 0"),
        ));
    }
    let socket = UdpSocket::bind(address)
        .and_then(|socket| socket.set_read_timeout(Some(RECEIVE_POLL)).map(|()| socket))
        .map_err(|e| {
            AgentError::invalid("--velodyne", format!("cannot listen on UDP {address}: {e}"))
        })?;
    tracing::info!(%address, "listening for Velodyne data packets");
    let idle = (idle_timeout_s > 0.0).then(|| Duration::from_secs_f64(idle_timeout_s));
    std::thread::Builder::new()
        .name("velodyne-udp".into())
        .spawn(move || {
            let reason = receive(&socket, idle, clock, &queue);
            queue.end(reason);
        })
        .map_err(|e| AgentError::Usage(format!("cannot start the UDP reader thread: {e}")))?;
    Ok(())
}

/// Receives until the idle timeout, a socket error or the run loop's end; returns why it stopped.
fn receive(
    socket: &UdpSocket,
    idle: Option<Duration>,
    clock: CaptureClock,
    queue: &ScanQueue,
) -> String {
    let mut buffer = [0u8; BUFFER_LEN];
    let mut assembler = RotationAssembler::new();
    let mut malformed = 0u64;
    let mut log = LogLimiter::new(MALFORMED_LOG_INTERVAL);
    let mut last_packet: Option<Instant> = None;
    let mut rotation_stamp = None;
    loop {
        let length = match socket.recv_from(&mut buffer) {
            Ok((length, _)) => length,
            Err(e)
                if matches!(
                    e.kind(),
                    std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
                ) =>
            {
                if let (Some(idle), Some(last)) = (idle, last_packet) {
                    if last.elapsed() >= idle {
                        return format!(
                            "no packet for {:.1} s (malformed packets: {malformed})",
                            idle.as_secs_f64()
                        );
                    }
                }
                continue;
            }
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
            Err(e) => return format!("receiving failed: {e}"),
        };
        let arrival = clock.now();
        last_packet = Some(Instant::now());
        let blocks = match decode_velodyne_packet(&buffer[..length]) {
            Ok((_, blocks)) => blocks,
            Err(error) => {
                malformed += 1;
                if let Some(suppressed) = log.allow("malformed") {
                    tracing::warn!(%error, malformed_total = malformed, suppressed, "malformed Velodyne packet skipped");
                }
                continue;
            }
        };
        for block in &blocks {
            if let Some(cloud) = assembler.push(block) {
                let stamp = rotation_stamp.take().unwrap_or(arrival);
                if !queue.offer(Captured::Scan { stamp, cloud }) {
                    return "the run ended".into();
                }
            }
            // The packet holding a rotation's first block stamps it.
            rotation_stamp.get_or_insert(arrival);
        }
    }
}
