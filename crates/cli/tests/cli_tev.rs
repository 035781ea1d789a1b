//! `lqmc render --tev HOST:PORT` streams the image to a listener speaking
//! tev's protocol: the test plays tev, decodes every packet and checks that
//! the last image it was sent is the image written to the file, bit for bit.

#[path = "../../render/tests/support/scratch_directory.rs"]
mod scratch_directory;
use scratch_directory::ScratchDirectory;

use std::io::Read;
use std::net::TcpListener;
use std::process::Command;

/// A decoded packet of tev's protocol (the types `lqmc` sends).
#[derive(Debug)]
enum Packet {
    /// CreateImage (type 4).
    Create {
        name: String,
        width: i32,
        height: i32,
        channels: Vec<String>,
    },
    /// UpdateImageV2 (type 5): a block of planar channel data.
    Update {
        name: String,
        channels: Vec<String>,
        block: [i32; 4],
        values: Vec<f32>,
    },
}

/// Reads fields of a packet's payload in order.
struct Fields<'a>(&'a [u8]);

impl Fields<'_> {
    fn byte(&mut self) -> u8 {
        let value = self.0[0];
        self.0 = &self.0[1..];
        value
    }
    fn integer(&mut self) -> i32 {
        let value = i32::from_le_bytes(self.0[..4].try_into().unwrap());
        self.0 = &self.0[4..];
        value
    }
    fn float(&mut self) -> f32 {
        f32::from_le_bytes(self.integer().to_le_bytes())
    }
    fn string(&mut self) -> String {
        let end = self.0.iter().position(|&byte| byte == 0).unwrap();
        let text = String::from_utf8(self.0[..end].to_vec()).unwrap();
        self.0 = &self.0[end + 1..];
        text
    }
}

/// Splits a byte stream into packets and decodes them.
fn decode(mut stream: &[u8]) -> Vec<Packet> {
    let mut packets = Vec::new();
    while !stream.is_empty() {
        let length = u32::from_le_bytes(stream[..4].try_into().unwrap()) as usize;
        let mut fields = Fields(&stream[5..length]);
        let packet = match stream[4] {
            4 => {
                let _grab_focus = fields.byte();
                let name = fields.string();
                let (width, height, count) = (fields.integer(), fields.integer(), fields.integer());
                let channels = (0..count).map(|_| fields.string()).collect();
                Packet::Create {
                    name,
                    width,
                    height,
                    channels,
                }
            }
            5 => {
                let _grab_focus = fields.byte();
                let name = fields.string();
                let count = fields.integer();
                let channels: Vec<String> = (0..count).map(|_| fields.string()).collect();
                let block = [
                    fields.integer(),
                    fields.integer(),
                    fields.integer(),
                    fields.integer(),
                ];
                let values = (0..block[2] * block[3] * count)
                    .map(|_| fields.float())
                    .collect();
                Packet::Update {
                    name,
                    channels,
                    block,
                    values,
                }
            }
            other => panic!("unexpected packet type {other}"),
        };
        assert!(fields.0.is_empty(), "bytes left in a packet");
        packets.push(packet);
        stream = &stream[length..];
    }
    packets
}

/// Renders with `--tev` to a listener and returns the decoded packets and
/// the written EXR.
fn render_streamed(name: &str, extra: &[&str]) -> (Vec<Packet>, render::image::ExrContents) {
    let directory = ScratchDirectory::new(name);
    let output = directory.join(format!("{name}.exr"));
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let address = listener.local_addr().unwrap().to_string();
    let receiver = std::thread::spawn(move || {
        let (mut connection, _) = listener.accept().unwrap();
        let mut bytes = Vec::new();
        connection.read_to_end(&mut bytes).unwrap();
        bytes
    });
    let mut args = vec![
        "render",
        "builtin:cornell-box",
        "--resolution",
        "40x30",
        "--quiet",
        "--tev",
        &address,
        "-o",
        output.to_str().unwrap(),
    ];
    args.extend(extra);
    let status = Command::new(env!("CARGO_BIN_EXE_lqmc"))
        .args(&args)
        .status()
        .unwrap();
    assert!(status.success());
    let bytes = receiver.join().unwrap();
    (decode(&bytes), render::image::read_exr(&output).unwrap())
}

/// Replays the updates onto a `width × height` image of `channels`
/// channels, checking that each full update covers every pixel once;
/// returns the image after the last full update.
fn last_image(packets: &[Packet], width: usize, height: usize) -> Vec<Vec<f32>> {
    let mut image = vec![vec![f32::NAN; width * height]; 6];
    let mut covered = vec![0u32; width * height];
    let mut updates = 0;
    for packet in packets {
        if let Packet::Update {
            channels,
            block: [x0, y0, block_width, block_height],
            values,
            ..
        } = packet
        {
            let (x0, y0) = (*x0 as usize, *y0 as usize);
            let (block_width, block_height) = (*block_width as usize, *block_height as usize);
            assert_eq!(channels.len(), 6);
            for (channel, plane) in values.chunks(block_width * block_height).enumerate() {
                for y in 0..block_height {
                    for x in 0..block_width {
                        image[channel][(y0 + y) * width + x0 + x] = plane[y * block_width + x];
                        if channel == 0 {
                            covered[(y0 + y) * width + x0 + x] += 1;
                        }
                    }
                }
            }
            updates += 1;
        }
    }
    assert!(updates > 0, "no update was sent");
    let first = covered[0];
    assert!(covered.iter().all(|&count| count == first && count > 0));
    image
}

fn assert_last_image_is_the_file(packets: &[Packet], contents: &render::image::ExrContents) {
    let Packet::Create {
        name,
        width,
        height,
        channels,
    } = &packets[0]
    else {
        panic!("the first packet creates the image: {:?}", packets[0]);
    };
    assert_eq!((*width, *height), (40, 30));
    assert_eq!(
        channels,
        &["R", "G", "B", "variance.R", "variance.G", "variance.B"]
    );
    for packet in packets {
        if let Packet::Update { name: updated, .. } = packet {
            assert_eq!(updated, name);
        }
    }
    let image = last_image(packets, 40, 30);
    let variance = &contents.layers[render::image::VARIANCE_LAYER];
    for (index, (pixel, variance)) in contents
        .image
        .pixels()
        .iter()
        .zip(variance.pixels())
        .enumerate()
    {
        for channel in 0..3 {
            assert_eq!(image[channel][index].to_bits(), pixel[channel].to_bits());
            assert_eq!(
                image[channel + 3][index].to_bits(),
                variance[channel].to_bits()
            );
        }
    }
}

#[test]
fn tev_stream_ends_with_the_written_image() {
    let (packets, contents) = render_streamed("tev_render", &["--spp", "8"]);
    assert_last_image_is_the_file(&packets, &contents);
}

#[test]
fn tev_stream_of_replications_ends_with_their_mean_and_variance() {
    let (packets, contents) =
        render_streamed("tev_replications", &["--spp", "8", "--replications", "4"]);
    assert_last_image_is_the_file(&packets, &contents);
}

#[test]
fn tev_address_that_does_not_answer_is_an_error_before_rendering() {
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let address = listener.local_addr().unwrap().to_string();
    drop(listener);
    let output = Command::new(env!("CARGO_BIN_EXE_lqmc"))
        .args([
            "render",
            "--resolution",
            "8x8",
            "--quiet",
            "--tev",
            &address,
        ])
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(2));
    let message = String::from_utf8(output.stderr).unwrap();
    assert!(message.contains(&address), "{message}");
}
