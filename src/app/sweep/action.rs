//! What the Sweep workspace's panels and menus ask for, carried out after the frame's UI
//! ([`super::SweepWorkspace::act`]). The results are read-only: the actions read folders and
//! rebuild designs, and nothing here has an undo step.

use std::path::PathBuf;

use super::CustomPlot;
use super::table::Sort;

/// A request the panels and menus queue.
#[derive(Debug, Clone, PartialEq)]
pub enum SweepAction {
    /// Ask for a results folder (a folder dialog).
    AskFolder,
    /// Read this results folder.
    OpenFolder(PathBuf),
    /// Stop reading the folder being read (the previous table stays).
    CancelLoad,
    /// Rebuild the design of this row (an index into the table) and open it in the workspace
    /// that made it (Display layouts or Phase masks): the current design, B in Compare.
    OpenRow(usize),
    /// Rebuild the display design of this row and pin it as A for Compare.
    PinRow(usize),
    /// Show the rows this filter keeps (see [`super::table::Filter`]).
    Filter(String),
    /// Sort the rows so.
    Sort(Sort),
    /// The user's own plot.
    Custom(CustomPlot),
    /// New study from the Display workspace's current design (asks it for the design).
    NewStudy,
    /// Stop the running study after the points in flight.
    CancelStudy,
    /// Run what is left of the study in the open results folder.
    ResumeStudy,
    /// Open Help ▸ Reproduce thesis results (the thesis's specs under `presets/reproduce/`).
    OpenReproduce,
    /// Run the shipped example sweep of this file name (`io::sweep::EXAMPLES`) in a new
    /// folder.
    RunExample(&'static str),
}
