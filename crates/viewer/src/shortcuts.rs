//! Keyboard shortcuts and the help overlay (F1) that lists them with the mouse controls.

use crate::app::ViewerApp;
use crate::io::DialogPurpose;
use crate::render::Shading;
use egui::{Key, KeyboardShortcut, Modifiers};

/// What a shortcut does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Action {
    /// Play / pause training.
    PlayPause,
    /// Present λ signals.
    Step,
    /// Restart training with the edited parameters.
    Reset,
    /// Reconstruct the neural mesh now.
    Reconstruct,
    /// Open a mesh file.
    Open,
    /// Save a screenshot.
    Screenshot,
    /// Toggle the wireframe.
    Wireframe,
    /// Toggle flat / smooth shading.
    Flat,
    /// Toggle the original overlay.
    Original,
    /// Toggle the base-colour texture.
    Texture,
    /// Frame the model again.
    ResetCamera,
    /// Show / hide the parameter panel.
    Controls,
    /// Show / hide the plots panel.
    Plots,
    /// Show / hide this help.
    Help,
    /// Close the window.
    Quit,
}

/// Every shortcut with its key and description, in help order.
pub const SHORTCUTS: [(KeyboardShortcut, Action, &str); 15] = [
    (
        plain(Key::Space),
        Action::PlayPause,
        "play / pause training",
    ),
    (plain(Key::S), Action::Step, "step: present λ signals"),
    (
        plain(Key::R),
        Action::Reset,
        "reset (applies edited parameters)",
    ),
    (
        plain(Key::N),
        Action::Reconstruct,
        "reconstruct the neural mesh now",
    ),
    (ctrl(Key::O), Action::Open, "open a mesh"),
    (ctrl(Key::S), Action::Screenshot, "save a screenshot (PNG)"),
    (plain(Key::W), Action::Wireframe, "wireframe on / off"),
    (plain(Key::F), Action::Flat, "flat / smooth shading"),
    (plain(Key::O), Action::Original, "original overlay on / off"),
    (plain(Key::T), Action::Texture, "texture on / off"),
    (plain(Key::Home), Action::ResetCamera, "reset the camera"),
    (plain(Key::C), Action::Controls, "parameter panel on / off"),
    (plain(Key::P), Action::Plots, "plots and table on / off"),
    (plain(Key::F1), Action::Help, "this help"),
    (ctrl(Key::Q), Action::Quit, "quit"),
];

/// Mouse controls, for the help overlay.
pub const MOUSE: [(&str, &str); 5] = [
    ("left drag", "orbit (both views share one camera)"),
    ("right / middle drag, shift + left drag", "pan"),
    ("wheel, pinch", "zoom"),
    ("double click", "reset the camera"),
    (
        "drop a file on the window",
        "open it (OBJ, PLY, STL, glTF, GLB)",
    ),
];

const fn plain(key: Key) -> KeyboardShortcut {
    KeyboardShortcut::new(Modifiers::NONE, key)
}

const fn ctrl(key: Key) -> KeyboardShortcut {
    KeyboardShortcut::new(Modifiers::COMMAND, key)
}

impl ViewerApp {
    /// Apply the shortcuts pressed this frame (none while a text field has the keyboard).
    pub(crate) fn shortcuts(&mut self, ctx: &egui::Context) {
        if ctx.egui_wants_keyboard_input() {
            return;
        }
        // Ctrl shortcuts first: `consume_shortcut` of a plain key would also match it.
        let mut ordered = SHORTCUTS;
        ordered.sort_by_key(|(s, _, _)| !s.modifiers.command);
        let pressed: Vec<Action> = ctx.input_mut(|i| {
            ordered
                .iter()
                .filter(|(s, _, _)| i.consume_shortcut(s))
                .map(|(_, a, _)| *a)
                .collect()
        });
        for action in pressed {
            self.apply(ctx, action);
        }
    }

    /// Do what `action` stands for.
    pub fn apply(&mut self, ctx: &egui::Context, action: Action) {
        let live = self.session.live().clone();
        match action {
            Action::PlayPause if !live.finished => self.session.set_running(!live.running),
            Action::PlayPause => {}
            Action::Step => self.step_once(),
            Action::Reset => self.session.reset_training(),
            Action::Reconstruct => self.session.reconstruct_now(),
            Action::Open => self.open_dialog(DialogPurpose::OpenMesh),
            Action::Screenshot => self.open_dialog(DialogPurpose::Screenshot),
            Action::Wireframe => self.display.wireframe ^= true,
            Action::Flat => {
                self.display.shading = match self.display.shading {
                    Shading::Flat => Shading::Smooth,
                    Shading::Smooth => Shading::Flat,
                }
            }
            Action::Original => self.display.show_original ^= true,
            Action::Texture => self.display.texture ^= true,
            Action::ResetCamera => self.reset_camera(),
            Action::Controls => self.panels_or_default().controls ^= true,
            Action::Plots => self.panels_or_default().plots ^= true,
            Action::Help => self.panels_or_default().help ^= true,
            Action::Quit => ctx.send_viewport_cmd(egui::ViewportCommand::Close),
        }
    }

    fn panels_or_default(&mut self) -> &mut crate::app::Panels {
        self.panels
            .get_or_insert_with(|| crate::app::Panels::for_width(1600.0))
    }

    /// The help window (F1), listing every shortcut and the mouse controls.
    pub(crate) fn help_overlay(&mut self, ctx: &egui::Context) {
        let Some(panels) = self.panels.as_mut() else {
            return;
        };
        let mut open = panels.help;
        egui::Window::new("Keyboard and mouse")
            .open(&mut open)
            .collapsible(false)
            .resizable(false)
            .anchor(egui::Align2::CENTER_CENTER, egui::Vec2::ZERO)
            .show(ctx, |ui| {
                egui::Grid::new("help_keys").num_columns(2).show(ui, |ui| {
                    for (shortcut, _, what) in SHORTCUTS {
                        ui.monospace(ctx.format_shortcut(&shortcut));
                        ui.label(what);
                        ui.end_row();
                    }
                    for (gesture, what) in MOUSE {
                        ui.monospace(gesture);
                        ui.label(what);
                        ui.end_row();
                    }
                });
            });
        panels.help = open;
    }
}
