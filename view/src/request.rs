//! What a picture shows ([`Picture`], [`Reference`]), as plain data the caller fills in, and the
//! pixel of a box's centre: below the picture and the parts it draws (the annotations, the
//! panel), which all read them.

use scenalog_facts::scene::{Frame, Scene, TrackBox, TrackId};

use crate::mark::Annotation;
use crate::view::View;

/// Whose frame the picture is drawn in: that object's heading points up.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Reference {
    /// The ego vehicle at the centre, heading up.
    Ego,
    /// The referred object at the centre, heading up.
    Referred,
}

/// What to draw: plain data, filled in by the caller.
#[derive(Debug, Clone)]
pub struct Picture<'a> {
    /// The scene.
    pub scene: &'a Scene,
    /// The frame drawn.
    pub frame: Frame,
    /// The point of view.
    pub reference: Reference,
    /// The referred object, highlighted.
    pub referred: Option<TrackId>,
    /// Whether [`Picture::referred`] is referred at this frame: `false` (a why-not picture)
    /// draws it in its category's colour with a dashed outline in the referred colour and no
    /// halo, so the picture does not show it as referred.
    pub referred_here: bool,
    /// Objects related to the referred one, outlined and linked to it.
    pub related: Vec<TrackId>,
    /// The proof's geometric facts.
    pub annotations: Vec<Annotation>,
    /// First line: the scenario's description.
    pub title: String,
    /// Lines under the time, e.g. `referred` or `NOT referred: S < 0.5 fails`.
    pub status: String,
    /// Lines of text listed in the panel (the proof's facts), each with whether it holds.
    pub notes: Vec<(String, bool)>,
    /// The map's width, pixels (the panel is added on its right: see [`layout`]).
    pub width: u32,
    /// The map's (and the picture's) height, pixels.
    pub height: u32,
    /// Metres shown either side of the centre at least (grown to fit the related objects).
    pub half_extent: f64,
}

impl<'a> Picture<'a> {
    /// A picture of `scene` at `frame` from the ego, an 800 × 800 px map, 30 m either side, with
    /// nothing highlighted: set the fields to add the match.
    pub fn new(scene: &'a Scene, frame: Frame) -> Picture<'a> {
        Picture {
            scene,
            frame,
            reference: Reference::Ego,
            referred: None,
            referred_here: true,
            related: Vec::new(),
            annotations: Vec::new(),
            title: String::new(),
            status: String::new(),
            notes: Vec::new(),
            width: 800,
            height: 800,
            half_extent: 30.0,
        }
    }
}

/// The pixel of a box's centre.
pub fn centre_px(view: &View, b: &TrackBox) -> [f64; 2] {
    let c = b.city_center();
    view.px([c.x, c.y])
}
