//! A client for the TCP protocol of the image viewer
//! [tev](https://github.com/Tom94/tev), so that `lqmc render --tev HOST:PORT`
//! can show the image while it renders, as pbrt-v4's `--display-server` does.
//!
//! tev listens on `127.0.0.1:14158` unless started with another `--hostname`.
//! The client creates an image with its channels, sends the pixels in
//! rectangular blocks (as often as the renderer likes), and closes the image.
//!
//! # Packet layout
//!
//! Sources (facts only; the code here is written from scratch): tev's
//! `include/tev/Ipc.h` and `src/Ipc.cpp` (`IpcPacket::set*`,
//! `IpcPacket::interpretAs*` and the `OStream`/`IStream` serialisation),
//! Thomas Müller's summary of the protocol in tev issue #116, tev pull request
//! #113 (which added `UpdateImageV2`), and pbrt-v4's
//! `src/pbrt/util/display.cpp` (how pbrt creates an image and sends tiles).
//!
//! Every packet is `[u32 total length][u8 type][payload]`. The length counts
//! the whole packet, its own 4 bytes included. Integers are little endian,
//! booleans one byte (0 or 1), strings UTF-8 bytes followed by a NUL. Pixel
//! values are IEEE 754 `f32`; tev reinterprets them in its own byte order, so
//! we write them little endian, the order of every host tev runs on in
//! practice (x86-64, ARM64).
//!
//! | packet | type | payload |
//! | --- | --- | --- |
//! | `CloseImage` | 2 | name |
//! | `CreateImage` | 4 | grab focus, name, width `i32`, height `i32`, channel count `i32`, channel names |
//! | `UpdateImageV2` | 5 | grab focus, name, channel count `i32`, channel names, x `i32`, y `i32`, width `i32`, height `i32`, pixel data |
//!
//! The pixel data of an update is planar: all `width × height` values of the
//! first channel (row by row, x fastest), then those of the second, and so on.
//!
//! # Which update packet
//!
//! We send `UpdateImageV2` (type 5). tev has accepted it since pull request
//! #113 (February 2021), and every tev since then still decodes all three
//! update types (3, 5 and 6; see `interpretAsUpdateImage`), so the releases in
//! use today accept it. The original `UpdateImage` (type 3, the one pbrt-v4
//! sends) carries a single channel, so tev would show R updated before G and B
//! (the flicker #113 removed) and needs one packet per channel; the only tev
//! versions it reaches beyond type 5 predate 2021. `UpdateImageV3` (type 6)
//! adds per-channel offsets and strides, which we do not need, and is newer,
//! so fewer installed versions accept it.
//!
//! # Block size
//!
//! An image is sent in blocks of at most [`BLOCK_SIZE`] × [`BLOCK_SIZE`] =
//! 128 × 128 pixels, pbrt-v4's tile size. One update packet then carries at
//! most 64 KiB of pixel data per channel: 192 KiB for RGB, 384 KiB for RGB
//! with a variance layer. That stays below the 1 MiB receive buffer tev
//! allocates per connection (a hard limit before #113; later versions grow
//! it for larger packets), and tev shows the image progressively instead of
//! waiting for one huge packet.
//!
//! # Failures
//!
//! Connecting times out after [`CONNECT_TIMEOUT`] and a write after
//! [`WRITE_TIMEOUT`] (so that a hung viewer cannot stall the renderer). A
//! failed write returns [`TevError::Send`] and drops the connection, since a
//! packet may have been cut in half; every later call returns
//! [`TevError::Disconnected`] at once, so the renderer can stop streaming and
//! warn once. Writing to a closed socket returns an error, never a panic or a
//! `SIGPIPE` (Rust ignores that signal and sends with `MSG_NOSIGNAL`).

use std::io::Write;
use std::net::{SocketAddr, TcpStream, ToSocketAddrs};
use std::time::Duration;

/// Where tev listens unless told otherwise.
pub const DEFAULT_ADDRESS: &str = "127.0.0.1:14158";

/// The side of the square blocks an image is sent in, in pixels (pbrt-v4's
/// tile size; see the module documentation).
pub const BLOCK_SIZE: u32 = 128;

/// How long [`TevClient::connect`] waits for each resolved address.
pub const CONNECT_TIMEOUT: Duration = Duration::from_secs(3);

/// How long one packet may take to be written before the connection is
/// given up.
pub const WRITE_TIMEOUT: Duration = Duration::from_secs(5);

#[cfg(test)]
/// The channels of a plain RGB image.
pub const RGB_CHANNELS: [&str; 3] = ["R", "G", "B"];

/// The channels of an RGB image with a per-pixel variance layer; tev shows
/// `variance` as a layer of its own.
pub const RGB_AND_VARIANCE_CHANNELS: [&str; 6] =
    ["R", "G", "B", "variance.R", "variance.G", "variance.B"];

#[cfg(test)]
/// Type code of `CloseImage` (tev `include/tev/Ipc.h`, `IpcPacket::EType`).
const CLOSE_IMAGE_TYPE: u8 = 2;
/// Type code of `CreateImage` (tev `include/tev/Ipc.h`, `IpcPacket::EType`).
const CREATE_IMAGE_TYPE: u8 = 4;
/// Type code of `UpdateImageV2` (tev `include/tev/Ipc.h`, `IpcPacket::EType`).
const UPDATE_IMAGE_V2_TYPE: u8 = 5;

/// The bytes in front of every payload: the length and the type.
const HEADER_LENGTH: usize = 5;

/// A failure to reach tev, to talk to it, or to encode a packet.
#[derive(Debug, thiserror::Error)]
pub enum TevError {
    /// The address is not `HOST:PORT` or resolves to nothing.
    #[error("tev address `{address}` is not HOST:PORT ({reason})")]
    InvalidAddress { address: String, reason: String },
    /// No resolved address accepted a connection in time.
    #[error("cannot connect to tev at {address}: {source}")]
    Connect {
        address: String,
        source: std::io::Error,
    },
    /// A write failed; the connection has been dropped.
    #[error("lost the connection to tev at {address}: {source}")]
    Send {
        address: String,
        source: std::io::Error,
    },
    /// An earlier write failed, so nothing more is sent.
    #[error("the connection to tev at {address} was lost earlier")]
    Disconnected { address: String },
    /// The arguments cannot be put into a packet (e.g. a NUL in a name).
    #[error("cannot encode a tev packet: {0}")]
    Encoding(String),
}

/// A rectangle of an image, in pixels: what one update packet carries.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ImageBlock {
    pub x: u32,
    pub y: u32,
    pub width: u32,
    pub height: u32,
}

/// The blocks of at most `block_size` × `block_size` pixels that tile a
/// `width` × `height` image, row of blocks by row of blocks; the last block
/// of a row or column is cut to the image. Each pixel lies in exactly one
/// block.
///
/// # Panics
///
/// If `block_size` is 0.
pub fn image_blocks(width: u32, height: u32, block_size: u32) -> impl Iterator<Item = ImageBlock> {
    assert!(block_size > 0, "tev blocks need a positive size");
    (0..height).step_by(block_size as usize).flat_map(move |y| {
        (0..width)
            .step_by(block_size as usize)
            .map(move |x| ImageBlock {
                x,
                y,
                width: block_size.min(width - x),
                height: block_size.min(height - y),
            })
    })
}

/// The bytes of a `CreateImage` packet: a black image of `width` × `height`
/// pixels with the given channels, which tev shows at once if `grab_focus`.
/// An image of the same name is replaced.
pub fn encode_create_image(
    name: &str,
    grab_focus: bool,
    width: u32,
    height: u32,
    channels: &[&str],
) -> Result<Vec<u8>, TevError> {
    check_channels(channels)?;
    let mut packet = PacketBuilder::new(CREATE_IMAGE_TYPE, name.len() + 32);
    packet.boolean(grab_focus);
    packet.string("image name", name)?;
    packet.integer("image width", width)?;
    packet.integer("image height", height)?;
    packet.integer("channel count", channels.len())?;
    for channel in channels {
        packet.string("channel name", channel)?;
    }
    packet.finish()
}

/// The bytes of an `UpdateImageV2` packet that sets the pixels of `block` in
/// every given channel, without grabbing focus. `pixel(x, y, channel)` gives
/// the value at image coordinates (`x`, `y`) of `channels[channel]`.
pub fn encode_update_block(
    name: &str,
    channels: &[&str],
    block: ImageBlock,
    pixel: impl Fn(u32, u32, usize) -> f32,
) -> Result<Vec<u8>, TevError> {
    check_channels(channels)?;
    let value_count = block.width as usize * block.height as usize * channels.len();
    let mut packet = PacketBuilder::new(
        UPDATE_IMAGE_V2_TYPE,
        name.len() + 64 + 4 * value_count + channels.iter().map(|c| c.len() + 1).sum::<usize>(),
    );
    packet.boolean(false);
    packet.string("image name", name)?;
    packet.integer("channel count", channels.len())?;
    for channel in channels {
        packet.string("channel name", channel)?;
    }
    packet.integer("block x", block.x)?;
    packet.integer("block y", block.y)?;
    packet.integer("block width", block.width)?;
    packet.integer("block height", block.height)?;
    for channel in 0..channels.len() {
        for y in block.y..block.y + block.height {
            for x in block.x..block.x + block.width {
                packet.float(pixel(x, y, channel));
            }
        }
    }
    packet.finish()
}

#[cfg(test)]
/// The update packets that send a whole `width` × `height` image in blocks
/// of at most `block_size` × `block_size` pixels (see [`image_blocks`] and
/// [`encode_update_block`]).
pub fn encode_update_image(
    name: &str,
    width: u32,
    height: u32,
    channels: &[&str],
    block_size: u32,
    pixel: impl Fn(u32, u32, usize) -> f32,
) -> Result<Vec<Vec<u8>>, TevError> {
    image_blocks(width, height, block_size)
        .map(|block| encode_update_block(name, channels, block, &pixel))
        .collect()
}

#[cfg(test)]
/// The bytes of a `CloseImage` packet: tev closes the image of that name.
pub fn encode_close_image(name: &str) -> Result<Vec<u8>, TevError> {
    let mut packet = PacketBuilder::new(CLOSE_IMAGE_TYPE, name.len() + 8);
    packet.string("image name", name)?;
    packet.finish()
}

/// Rejects an empty channel list: tev needs at least one channel.
fn check_channels(channels: &[&str]) -> Result<(), TevError> {
    if channels.is_empty() {
        return Err(TevError::Encoding(
            "an image needs at least one channel".into(),
        ));
    }
    Ok(())
}

/// Appends the fields of one packet in tev's encoding and writes the length
/// in front when done.
struct PacketBuilder {
    bytes: Vec<u8>,
}

impl PacketBuilder {
    /// Starts a packet of the given type, with room for `capacity` bytes.
    fn new(packet_type: u8, capacity: usize) -> PacketBuilder {
        let mut bytes = Vec::with_capacity(capacity.max(HEADER_LENGTH));
        // The length is filled in by `finish`.
        bytes.extend_from_slice(&[0, 0, 0, 0, packet_type]);
        PacketBuilder { bytes }
    }

    fn boolean(&mut self, value: bool) {
        self.bytes.push(u8::from(value));
    }

    /// A NUL-terminated string; `what` names it in the error if the string
    /// itself holds a NUL, which tev would take for its end.
    fn string(&mut self, what: &str, value: &str) -> Result<(), TevError> {
        if value.contains('\0') {
            return Err(TevError::Encoding(format!(
                "the {what} {value:?} contains a NUL character"
            )));
        }
        self.bytes.extend_from_slice(value.as_bytes());
        self.bytes.push(0);
        Ok(())
    }

    /// A little-endian `i32` (tev's `int32_t` fields); `what` names the value
    /// in the error if it does not fit.
    fn integer(
        &mut self,
        what: &str,
        value: impl TryInto<i32> + Copy + std::fmt::Display,
    ) -> Result<(), TevError> {
        let Ok(integer) = value.try_into() else {
            return Err(TevError::Encoding(format!(
                "the {what} {value} exceeds tev's limit of {}",
                i32::MAX
            )));
        };
        self.bytes.extend_from_slice(&integer.to_le_bytes());
        Ok(())
    }

    fn float(&mut self, value: f32) {
        self.bytes.extend_from_slice(&value.to_le_bytes());
    }

    /// Writes the total length into the first four bytes.
    fn finish(mut self) -> Result<Vec<u8>, TevError> {
        let Ok(length) = u32::try_from(self.bytes.len()) else {
            return Err(TevError::Encoding(format!(
                "a packet of {} bytes exceeds tev's limit of {} bytes",
                self.bytes.len(),
                u32::MAX
            )));
        };
        self.bytes[..4].copy_from_slice(&length.to_le_bytes());
        Ok(self.bytes)
    }
}

/// A connection to a running tev.
pub struct TevClient {
    /// The address as the user gave it, for messages.
    address: String,
    /// `None` once a write has failed.
    stream: Option<TcpStream>,
}

impl TevClient {
    /// Connects to tev at `address` (`HOST:PORT`, e.g. [`DEFAULT_ADDRESS`]),
    /// trying each address the host resolves to for at most
    /// [`CONNECT_TIMEOUT`]. Resolving a host name is left to the system and
    /// has no timeout of ours.
    pub fn connect(address: &str) -> Result<TevClient, TevError> {
        let invalid = |reason: String| TevError::InvalidAddress {
            address: address.to_owned(),
            reason,
        };
        let resolved: Vec<SocketAddr> = address
            .to_socket_addrs()
            .map_err(|error| invalid(error.to_string()))?
            .collect();
        if resolved.is_empty() {
            return Err(invalid("the host resolves to no address".into()));
        }
        let connect_error = |source| TevError::Connect {
            address: address.to_owned(),
            source,
        };
        let mut last_error = None;
        for socket_address in &resolved {
            match TcpStream::connect_timeout(socket_address, CONNECT_TIMEOUT) {
                Ok(stream) => {
                    stream
                        .set_write_timeout(Some(WRITE_TIMEOUT))
                        .map_err(connect_error)?;
                    // Small packets (create, close) go out at once.
                    stream.set_nodelay(true).map_err(connect_error)?;
                    return Ok(TevClient {
                        address: address.to_owned(),
                        stream: Some(stream),
                    });
                }
                Err(error) => last_error = Some(error),
            }
        }
        let source = last_error.unwrap_or_else(|| std::io::Error::other("no address to try"));
        Err(connect_error(source))
    }

    #[cfg(test)]
    /// The address as given to [`TevClient::connect`].
    pub fn address(&self) -> &str {
        &self.address
    }

    /// Creates (or replaces) a black image of `width` × `height` pixels with
    /// the given channels, e.g. [`RGB_CHANNELS`], and brings it to the front.
    pub fn create_image(
        &mut self,
        name: &str,
        width: u32,
        height: u32,
        channels: &[&str],
    ) -> Result<(), TevError> {
        let packet = encode_create_image(name, true, width, height, channels)?;
        self.send(&packet)
    }

    /// Sends every pixel of the image `name` (created with the same size and
    /// channels) in blocks of at most [`BLOCK_SIZE`] × [`BLOCK_SIZE`].
    /// `pixel(x, y, channel)` gives the value at (`x`, `y`) of
    /// `channels[channel]`. One block is encoded and written at a time, so
    /// memory stays at one packet.
    pub fn update_image(
        &mut self,
        name: &str,
        width: u32,
        height: u32,
        channels: &[&str],
        pixel: impl Fn(u32, u32, usize) -> f32,
    ) -> Result<(), TevError> {
        self.update_image_in_blocks(name, width, height, channels, BLOCK_SIZE, pixel)
    }

    /// [`TevClient::update_image`] with a chosen block size (the tests use
    /// small blocks to split small images).
    fn update_image_in_blocks(
        &mut self,
        name: &str,
        width: u32,
        height: u32,
        channels: &[&str],
        block_size: u32,
        pixel: impl Fn(u32, u32, usize) -> f32,
    ) -> Result<(), TevError> {
        for block in image_blocks(width, height, block_size) {
            let packet = encode_update_block(name, channels, block, &pixel)?;
            self.send(&packet)?;
        }
        Ok(())
    }

    #[cfg(test)]
    /// Closes the image `name` in tev.
    pub fn close_image(&mut self, name: &str) -> Result<(), TevError> {
        let packet = encode_close_image(name)?;
        self.send(&packet)
    }

    /// Writes one whole packet; on failure drops the connection, since tev
    /// cannot find the next packet after a partial one.
    fn send(&mut self, packet: &[u8]) -> Result<(), TevError> {
        let Some(stream) = self.stream.as_mut() else {
            return Err(TevError::Disconnected {
                address: self.address.clone(),
            });
        };
        if let Err(source) = stream.write_all(packet) {
            self.stream = None;
            return Err(TevError::Send {
                address: self.address.clone(),
                source,
            });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Read;
    use std::net::TcpListener;

    /// A packet as decoded by the test's own reader of tev's layout: tev's
    /// `CreateImage`, `UpdateImageV2` and `CloseImage`.
    #[derive(Debug, Clone, PartialEq)]
    enum DecodedPacket {
        Create {
            grab_focus: bool,
            name: String,
            width: i32,
            height: i32,
            channels: Vec<String>,
        },
        Update {
            grab_focus: bool,
            name: String,
            channels: Vec<String>,
            block: ImageBlock,
            /// Per channel, the bits of the block's values, row by row.
            values: Vec<Vec<u32>>,
        },
        Close {
            name: String,
        },
    }

    /// Reads fields from the front of a packet, panicking on malformed data.
    struct FieldReader<'a> {
        bytes: &'a [u8],
        position: usize,
    }

    impl FieldReader<'_> {
        fn take(&mut self, count: usize) -> &[u8] {
            assert!(
                self.position + count <= self.bytes.len(),
                "field runs past the end of the packet"
            );
            let field = &self.bytes[self.position..self.position + count];
            self.position += count;
            field
        }

        fn byte(&mut self) -> u8 {
            self.take(1)[0]
        }

        fn boolean(&mut self) -> bool {
            match self.byte() {
                0 => false,
                1 => true,
                other => panic!("boolean byte {other}"),
            }
        }

        fn integer(&mut self) -> i32 {
            i32::from_le_bytes(self.take(4).try_into().unwrap())
        }

        fn float_bits(&mut self) -> u32 {
            u32::from_le_bytes(self.take(4).try_into().unwrap())
        }

        fn string(&mut self) -> String {
            let rest = &self.bytes[self.position..];
            let end = rest.iter().position(|&byte| byte == 0).expect("no NUL");
            let text = std::str::from_utf8(&rest[..end]).unwrap().to_owned();
            self.position += end + 1;
            text
        }
    }

    /// Decodes one whole packet, checking its length prefix and that every
    /// byte is used.
    fn decode_packet(bytes: &[u8]) -> DecodedPacket {
        let mut reader = FieldReader { bytes, position: 0 };
        let length = u32::from_le_bytes(reader.take(4).try_into().unwrap());
        assert_eq!(length as usize, bytes.len(), "length prefix");
        let packet = match reader.byte() {
            CREATE_IMAGE_TYPE => {
                let grab_focus = reader.boolean();
                let name = reader.string();
                let width = reader.integer();
                let height = reader.integer();
                let count = reader.integer();
                let channels = (0..count).map(|_| reader.string()).collect();
                DecodedPacket::Create {
                    grab_focus,
                    name,
                    width,
                    height,
                    channels,
                }
            }
            UPDATE_IMAGE_V2_TYPE => {
                let grab_focus = reader.boolean();
                let name = reader.string();
                let count = reader.integer();
                let channels: Vec<String> = (0..count).map(|_| reader.string()).collect();
                let [x, y, width, height] = [(); 4].map(|()| reader.integer() as u32);
                let block = ImageBlock {
                    x,
                    y,
                    width,
                    height,
                };
                let pixel_count = (width * height) as usize;
                let values = channels
                    .iter()
                    .map(|_| (0..pixel_count).map(|_| reader.float_bits()).collect())
                    .collect();
                DecodedPacket::Update {
                    grab_focus,
                    name,
                    channels,
                    block,
                    values,
                }
            }
            CLOSE_IMAGE_TYPE => DecodedPacket::Close {
                name: reader.string(),
            },
            other => panic!("unexpected packet type {other}"),
        };
        assert_eq!(reader.position, bytes.len(), "trailing bytes");
        packet
    }

    /// Splits a byte stream into packets by their length prefixes.
    fn split_packets(mut stream: &[u8]) -> Vec<&[u8]> {
        let mut packets = Vec::new();
        while !stream.is_empty() {
            assert!(stream.len() >= HEADER_LENGTH, "truncated header");
            let length = u32::from_le_bytes(stream[..4].try_into().unwrap()) as usize;
            assert!(
                length >= HEADER_LENGTH && length <= stream.len(),
                "bad length {length}"
            );
            packets.push(&stream[..length]);
            stream = &stream[length..];
        }
        packets
    }

    /// A value for every pixel and channel whose bits vary everywhere, with
    /// negative zero, a subnormal, infinity and a NaN payload among them
    /// (signalling NaNs are avoided: some hardware quiets them in transit).
    fn test_value(seed: u32, x: u32, y: u32, channel: usize) -> f32 {
        let mut hash = seed
            .wrapping_mul(0x9e37_79b9)
            .wrapping_add(x.wrapping_mul(0x85eb_ca6b))
            .wrapping_add(y.wrapping_mul(0xc2b2_ae35))
            .wrapping_add((channel as u32).wrapping_mul(0x27d4_eb2f));
        hash ^= hash >> 15;
        hash = hash.wrapping_mul(0x2c1b_3c6d);
        hash ^= hash >> 12;
        match hash % 16 {
            0 => -0.0,
            1 => f32::from_bits(0x0000_0001),
            2 => f32::INFINITY,
            3 => f32::from_bits(0x7fc0_1234),
            _ => {
                let value = f32::from_bits(hash);
                if value.is_nan() { 0.5 } else { value }
            }
        }
    }

    #[test]
    fn tev_create_image_packet_round_trips() {
        for grab_focus in [false, true] {
            let packet = encode_create_image(
                "cornell (É)",
                grab_focus,
                640,
                480,
                &RGB_AND_VARIANCE_CHANNELS,
            )
            .unwrap();
            assert_eq!(packet[4], 4, "type code of CreateImage");
            assert_eq!(
                decode_packet(&packet),
                DecodedPacket::Create {
                    grab_focus,
                    name: "cornell (É)".into(),
                    width: 640,
                    height: 480,
                    channels: RGB_AND_VARIANCE_CHANNELS.map(String::from).to_vec(),
                }
            );
        }
    }

    #[test]
    fn tev_update_image_packets_round_trip_every_pixel() {
        let (width, height) = (300, 140);
        let channels = ["R", "variance.R"];
        let pixel = |x, y, channel| test_value(7, x, y, channel);
        let packets = encode_update_image("scene", width, height, &channels, 128, pixel).unwrap();
        let expected_blocks: Vec<ImageBlock> =
            [(0, 0, 128, 128), (128, 0, 128, 128), (256, 0, 44, 128)]
                .into_iter()
                .chain([(0, 128, 128, 12), (128, 128, 128, 12), (256, 128, 44, 12)])
                .map(|(x, y, width, height)| ImageBlock {
                    x,
                    y,
                    width,
                    height,
                })
                .collect();
        assert_eq!(packets.len(), expected_blocks.len());
        for (packet, expected_block) in packets.iter().zip(&expected_blocks) {
            assert_eq!(packet[4], 5, "type code of UpdateImageV2");
            let DecodedPacket::Update {
                grab_focus,
                name,
                channels: decoded_channels,
                block,
                values,
            } = decode_packet(packet)
            else {
                panic!("not an update packet");
            };
            assert!(!grab_focus);
            assert_eq!(name, "scene");
            assert_eq!(decoded_channels, channels);
            assert_eq!(block, *expected_block);
            for (channel, channel_values) in values.iter().enumerate() {
                let expected: Vec<u32> = (block.y..block.y + block.height)
                    .flat_map(|y| (block.x..block.x + block.width).map(move |x| (x, y)))
                    .map(|(x, y)| pixel(x, y, channel).to_bits())
                    .collect();
                assert_eq!(*channel_values, expected, "channel {channel} of {block:?}");
            }
        }
    }

    #[test]
    fn tev_close_image_packet_round_trips() {
        let packet = encode_close_image("scene: 16 spp").unwrap();
        assert_eq!(packet[4], 2, "type code of CloseImage");
        assert_eq!(
            decode_packet(&packet),
            DecodedPacket::Close {
                name: "scene: 16 spp".into()
            }
        );
    }

    #[test]
    fn tev_image_blocks_cover_every_pixel_once() {
        for (width, height, block_size) in [
            (0, 5, 4),
            (5, 0, 4),
            (1, 1, 128),
            (37, 23, 8),
            (256, 128, 128),
            (257, 129, 128),
        ] {
            let mut covered = vec![0u32; (width * height) as usize];
            for block in image_blocks(width, height, block_size) {
                assert!(block.width >= 1 && block.width <= block_size);
                assert!(block.height >= 1 && block.height <= block_size);
                for y in block.y..block.y + block.height {
                    for x in block.x..block.x + block.width {
                        covered[(y * width + x) as usize] += 1;
                    }
                }
            }
            assert!(
                covered.iter().all(|&count| count == 1),
                "{width}x{height} in {block_size}"
            );
        }
    }

    #[test]
    fn tev_update_packets_stay_below_tev_receive_buffer() {
        let block = ImageBlock {
            x: 0,
            y: 0,
            width: BLOCK_SIZE,
            height: BLOCK_SIZE,
        };
        let packet = encode_update_block(
            "a long image name",
            &RGB_AND_VARIANCE_CHANNELS,
            block,
            |_, _, _| 1.0,
        )
        .unwrap();
        assert!(packet.len() < 1 << 20, "{} bytes", packet.len());
    }

    #[test]
    fn tev_invalid_packets_are_rejected() {
        let block = ImageBlock {
            x: 0,
            y: 0,
            width: 1,
            height: 1,
        };
        let errors = [
            encode_create_image("a\0b", true, 1, 1, &RGB_CHANNELS).unwrap_err(),
            encode_create_image("a", true, 1, 1, &["R", "G\0"]).unwrap_err(),
            encode_create_image("a", true, 1, 1, &[]).unwrap_err(),
            encode_create_image("a", true, u32::MAX, 1, &RGB_CHANNELS).unwrap_err(),
            encode_update_block("a", &[], block, |_, _, _| 0.0).unwrap_err(),
            encode_close_image("\0").unwrap_err(),
        ];
        for error in errors {
            assert!(matches!(error, TevError::Encoding(_)), "{error}");
        }
    }

    #[test]
    fn tev_listener_reassembles_streamed_image_bit_for_bit() {
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let address = listener.local_addr().unwrap().to_string();
        let server = std::thread::spawn(move || {
            let (mut stream, _) = listener.accept().unwrap();
            stream
                .set_read_timeout(Some(Duration::from_secs(60)))
                .unwrap();
            let mut received = Vec::new();
            stream.read_to_end(&mut received).unwrap();
            received
        });

        let (width, height) = (37, 23);
        let mut client = TevClient::connect(&address).unwrap();
        assert_eq!(client.address(), address);
        client
            .create_image("stream", width, height, &RGB_CHANNELS)
            .unwrap();
        // First in 8 × 8 blocks (5 × 3 of them, cut at the edges), then in
        // one block of the default size.
        client
            .update_image_in_blocks("stream", width, height, &RGB_CHANNELS, 8, |x, y, c| {
                test_value(1, x, y, c)
            })
            .unwrap();
        client
            .update_image("stream", width, height, &RGB_CHANNELS, |x, y, c| {
                test_value(2, x, y, c)
            })
            .unwrap();
        client.close_image("stream").unwrap();
        drop(client);

        let received = server.join().unwrap();
        let packets: Vec<DecodedPacket> = split_packets(&received)
            .into_iter()
            .map(decode_packet)
            .collect();
        assert_eq!(
            packets.first(),
            Some(&DecodedPacket::Create {
                grab_focus: true,
                name: "stream".into(),
                width: 37,
                height: 23,
                channels: RGB_CHANNELS.map(String::from).to_vec(),
            })
        );
        assert_eq!(
            packets.last(),
            Some(&DecodedPacket::Close {
                name: "stream".into()
            })
        );
        let updates = &packets[1..packets.len() - 1];
        assert_eq!(updates.len(), 15 + 1);

        // Reassemble each update pass into an image and check every value.
        for (seed, pass) in [(1, &updates[..15]), (2, &updates[15..])] {
            let pixel_count = (width * height) as usize;
            let mut image = vec![[0u32; 3]; pixel_count];
            let mut written = vec![0u32; pixel_count];
            for update in pass {
                let DecodedPacket::Update {
                    grab_focus,
                    name,
                    channels,
                    block,
                    values,
                } = update
                else {
                    panic!("expected an update, got {update:?}");
                };
                assert!(!grab_focus);
                assert_eq!(name, "stream");
                assert_eq!(*channels, RGB_CHANNELS);
                assert!(block.x + block.width <= width && block.y + block.height <= height);
                for row in 0..block.height {
                    for column in 0..block.width {
                        let index = ((block.y + row) * width + block.x + column) as usize;
                        let offset = (row * block.width + column) as usize;
                        written[index] += 1;
                        for (channel, bits) in image[index].iter_mut().enumerate() {
                            *bits = values[channel][offset];
                        }
                    }
                }
            }
            assert!(written.iter().all(|&count| count == 1), "pass {seed}");
            for y in 0..height {
                for x in 0..width {
                    let pixel = image[(y * width + x) as usize];
                    for (channel, bits) in pixel.into_iter().enumerate() {
                        assert_eq!(
                            bits,
                            test_value(seed, x, y, channel).to_bits(),
                            "pass {seed}, pixel ({x}, {y}), channel {channel}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn tev_connecting_to_closed_port_names_the_address() {
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let address = listener.local_addr().unwrap().to_string();
        drop(listener);
        let error = TevClient::connect(&address)
            .err()
            .expect("connected to a closed port");
        assert!(matches!(error, TevError::Connect { .. }), "{error}");
        assert!(error.to_string().contains(&address), "{error}");
    }

    #[test]
    fn tev_unparsable_address_is_named() {
        for address in ["no-port-here", "127.0.0.1:not-a-port", "127.0.0.1:99999"] {
            let error = TevClient::connect(address)
                .err()
                .expect("accepted a bad address");
            assert!(matches!(error, TevError::InvalidAddress { .. }), "{error}");
            assert!(error.to_string().contains(address), "{error}");
        }
    }

    #[test]
    fn tev_writing_after_viewer_closes_returns_errors() {
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let address = listener.local_addr().unwrap().to_string();
        let server = std::thread::spawn(move || drop(listener.accept().unwrap()));
        let mut client = TevClient::connect(&address).unwrap();
        server.join().unwrap();

        let mut first_error = None;
        for _ in 0..1000 {
            if let Err(error) = client.update_image("gone", 128, 128, &RGB_CHANNELS, |_, _, _| 0.25)
            {
                first_error = Some(error);
                break;
            }
        }
        let error = first_error.expect("writes to a closed connection kept succeeding");
        assert!(matches!(error, TevError::Send { .. }), "{error}");
        assert!(error.to_string().contains(&address), "{error}");
        let later = client.close_image("gone").unwrap_err();
        assert!(matches!(later, TevError::Disconnected { .. }), "{later}");
    }
}
