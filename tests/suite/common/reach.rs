//! How the tests reach the studio's workspaces: through the shell's one generic accessor
//! ([`StudioApp::ws`]), named here once per workspace. Everything else a test reads is the
//! workspace's own (`app.display().design()`).

use udc_studio::app::phase::PhaseWorkspace;
use udc_studio::app::sensor::SensorWorkspace;
use udc_studio::app::sweep::SweepWorkspace;
use udc_studio::app::{DisplayAction, DisplayWorkspace, StudioApp};

/// The four workspaces of a [`StudioApp`], read-only and mutable, and the display workspace's
/// actions carried out as their menu items would.
pub trait Reach {
    fn display(&self) -> &DisplayWorkspace;
    fn display_mut(&mut self) -> &mut DisplayWorkspace;
    fn phase(&self) -> &PhaseWorkspace;
    fn phase_mut(&mut self) -> &mut PhaseWorkspace;
    fn sensor(&self) -> &SensorWorkspace;
    fn sensor_mut(&mut self) -> &mut SensorWorkspace;
    fn sweep(&self) -> &SweepWorkspace;
    fn sweep_mut(&mut self) -> &mut SweepWorkspace;
    /// Runs a display action as if its menu item, shortcut or button had been used.
    fn act(&mut self, action: DisplayAction);
}

impl Reach for StudioApp {
    fn display(&self) -> &DisplayWorkspace {
        self.ws()
    }
    fn display_mut(&mut self) -> &mut DisplayWorkspace {
        self.ws_mut()
    }
    fn phase(&self) -> &PhaseWorkspace {
        self.ws()
    }
    fn phase_mut(&mut self) -> &mut PhaseWorkspace {
        self.ws_mut()
    }
    fn sensor(&self) -> &SensorWorkspace {
        self.ws()
    }
    fn sensor_mut(&mut self) -> &mut SensorWorkspace {
        self.ws_mut()
    }
    fn sweep(&self) -> &SweepWorkspace {
        self.ws()
    }
    fn sweep_mut(&mut self) -> &mut SweepWorkspace {
        self.ws_mut()
    }
    fn act(&mut self, action: DisplayAction) {
        self.ws_with_shell(|ws: &mut DisplayWorkspace, shell| ws.act(action, shell));
    }
}

/// Whether the display workspace shows the full-quality result of its design (a
/// `step_until` condition).
pub fn display_up_to_date(app: &StudioApp) -> bool {
    app.display().is_up_to_date()
}
