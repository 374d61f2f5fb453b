//! What the window shows and where: the display toggles ([`Display`]), which panels are open
//! ([`Panels`]) and where the last frame drew them ([`PanelRects`]), and the start-up decision
//! on the parameter panel. Plain state, shared by the app, the panels and the scene (which
//! import it from here, not from each other).

use crate::render::Shading;

/// Height of the step strip before its first frame (one row of entries and its time bar).
pub const STRIP_HEIGHT_GUESS: f32 = 36.0;

/// Display toggles.
#[derive(Debug, Clone, PartialEq)]
pub struct Display {
    /// Flat or smooth shading of surfaces.
    pub shading: Shading,
    /// Draw mesh edges over surfaces.
    pub wireframe: bool,
    /// Draw the original mesh translucently over both views.
    pub show_original: bool,
    /// Draw the model's base-colour texture on the meshes with texture coordinates (when it
    /// has one).
    pub texture: bool,
    /// Draw the live network (nodes and edges) in the left view.
    pub show_network: bool,
    /// Draw the GNG3D reconstruction in the left view when there is one.
    pub show_gng_mesh: bool,
    /// Node diameter in pixels.
    pub point_px: f32,
    /// Anti-alias the UI's own shapes (egui "feathering"); switching it off saves about 1 ms per
    /// frame on a software renderer.
    pub smooth_ui: bool,
}

impl Default for Display {
    fn default() -> Self {
        Display {
            shading: Shading::Smooth,
            wireframe: false,
            show_original: false,
            texture: true,
            show_network: true,
            show_gng_mesh: true,
            point_px: 4.0,
            smooth_ui: true,
        }
    }
}

/// Which panels are open (all collapsible, so the viewports can take the window).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Panels {
    /// The parameter panel on the left.
    pub controls: bool,
    /// The plots and table at the bottom.
    pub plots: bool,
    /// The GNG3D step strip under the viewports.
    pub steps: bool,
    /// The table of every GNG3D step (a window over the views).
    pub step_details: bool,
    /// The keyboard/mouse help overlay (F1).
    pub help: bool,
    /// Which of the plot columns are shown: vertex errors, E_sur, Hausdorff, table.
    pub columns: [bool; 4],
    /// The window with every checkpoint of the run.
    pub history: bool,
}

impl Panels {
    /// Panels for a window `width` points wide: below 1350 points the parameter panel starts
    /// closed (C opens it), so the viewports keep at least half of the window (issue 13: down
    /// to 800×600) and the plots panel still has the height Table 1 and the plots need (issue
    /// 37: at 1280×720 the open panel left the plots 92 points).
    ///
    /// That is the width half of the start-up rule. The other half is the height: the first
    /// frame (`ViewerApp::layout`) also closes the panel when, open, it would leave the plots
    /// panel a height cap ([`crate::panels::plots_max_height`], measured with the panel's
    /// actual width) under [`crate::panels::PLOTS_WANTED_HEIGHT`] — 1366×768, 1400×800 and
    /// 1440×900 start with it closed, 1600×900 and 1920×1080 with it open. `--controls
    /// open|closed` overrides both. The rule applies once: after the first frame the panels
    /// are the user's (C, the `Parameters` button, the View menu) and resizing the window
    /// keeps them; the plots' cap still keeps the viewports half of the window.
    pub fn for_width(width: f32) -> Panels {
        Panels {
            controls: width >= 1350.0,
            plots: true,
            steps: true,
            step_details: false,
            help: false,
            columns: [true; 4],
            history: false,
        }
    }
}

/// Where the first frame is in deciding whether the parameter panel starts open (see
/// [`Panels::for_width`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum ControlsStart {
    /// Not yet laid out.
    Undecided,
    /// Laid out once (egui's first, narrow pass of its grids): measured in the next pass.
    Primed,
    /// Decided (or set by the user, or by `--controls`).
    Decided,
}

/// Where the panels around the viewports were drawn in the last frame, points: what a test
/// checks for "no panel over another" (`None`: not shown).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PanelRects {
    /// The parameter panel on the left.
    pub controls: Option<egui::Rect>,
    /// The status bar at the bottom of the window.
    pub status: Option<egui::Rect>,
    /// The plots panel, margins included (what its height cap and
    /// [`crate::panels::PLOTS_WANTED_HEIGHT`] are about).
    pub plots_panel: Option<egui::Rect>,
    /// The area the plots panel gave its contents (the panel less its margins).
    pub plots: Option<egui::Rect>,
    /// Everything the plots panel drew: its button row and the row of plots and Table 1.
    pub plots_content: Option<egui::Rect>,
    /// The plots panel's button row ("Hide plots", the column toggles, "Export CSV…").
    pub plots_toolbar: Option<egui::Rect>,
    /// The step strip (its entries and time bar) between the plots and the viewports.
    pub strip: Option<egui::Rect>,
}
