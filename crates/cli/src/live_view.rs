//! The live view of `lqmc render --tev HOST:PORT`: the image while it
//! renders, sent to the viewer tev ([`crate::tev`]) after each pass at most
//! every [`LiveView::INTERVAL`], and once more when the render ends. A
//! render of replications shows its first replication as it renders, then
//! the mean of the finished replications with the variance layer.
//!
//! The view never stops a render: when tev goes away, one warning is
//! printed and the render goes on without it.

use crate::tev::{RGB_AND_VARIANCE_CHANNELS, TevClient, TevError};
use render::film::Film;
use render::image::Image;
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// A render's image in tev.
pub struct LiveView {
    /// The connection, dropped after the first failure.
    client: Mutex<Option<TevClient>>,
    /// The image's name in tev (the output file's name).
    name: String,
    width: u32,
    height: u32,
    /// When the image was last sent.
    last_sent: Mutex<Option<Instant>>,
}

impl LiveView {
    /// How often the image is sent at most while rendering.
    pub const INTERVAL: Duration = Duration::from_millis(500);

    /// Connects to tev at `address` and creates the image `name` of
    /// `width × height` pixels with RGB and variance channels.
    pub fn open(address: &str, name: &str, width: u32, height: u32) -> Result<Self, TevError> {
        let mut client = TevClient::connect(address)?;
        client.create_image(name, width, height, &RGB_AND_VARIANCE_CHANNELS)?;
        Ok(Self {
            client: Mutex::new(Some(client)),
            name: name.to_string(),
            width,
            height,
            last_sent: Mutex::new(None),
        })
    }

    /// Shows `film` scaled by `splat_scale` (a render's pass observer), if
    /// the last image went out at least [`Self::INTERVAL`] ago.
    pub fn show_film(&self, film: &Film, splat_scale: f64) {
        if self.due() {
            self.show(&film.image(splat_scale), None);
        }
    }

    /// Shows `image` with its `variance` layer (zeros without one) now.
    pub fn show(&self, image: &Image, variance: Option<&Image>) {
        let Ok(mut client) = self.client.lock() else {
            return;
        };
        let Some(connection) = client.as_mut() else {
            return;
        };
        let width = image.width();
        let result = connection.update_image(
            &self.name,
            self.width,
            self.height,
            &RGB_AND_VARIANCE_CHANNELS,
            |x, y, channel| {
                let index = y as usize * width + x as usize;
                match (channel, variance) {
                    (0..=2, _) => image.pixels()[index][channel],
                    (_, Some(variance)) => variance.pixels()[index][channel - 3],
                    (_, None) => 0.0,
                }
            },
        );
        if let Err(error) = result {
            eprintln!("lqmc: warning: the live view stopped: {error}");
            *client = None;
        }
        if let Ok(mut last_sent) = self.last_sent.lock() {
            *last_sent = Some(Instant::now());
        }
    }

    /// True if the image is due to be sent again.
    fn due(&self) -> bool {
        self.last_sent.lock().is_ok_and(|last_sent| {
            last_sent.is_none_or(|instant| instant.elapsed() >= Self::INTERVAL)
        })
    }
}
