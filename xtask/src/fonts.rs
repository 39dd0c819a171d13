//! The font plot labels are drawn with, embedded in the binary so that reports render the
//! same on a machine without fontconfig or any system font (CI, a fresh GPU host).

use std::sync::Once;

use plotters::style::{FontStyle, register_font};

/// The family name plots ask for; registered here with an embedded typeface.
pub const PLOT_FONT: &str = "sans-serif";

/// Registers the embedded typeface under `PLOT_FONT` (once per process).
pub fn register_plot_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // Ubuntu Light ships in `epaint_default_fonts` under the Ubuntu Font Licence; the bytes
        // are a valid TrueType file, so registration can only fail on a broken build.
        if register_font(
            PLOT_FONT,
            FontStyle::Normal,
            epaint_default_fonts::UBUNTU_LIGHT,
        )
        .is_err()
        {
            eprintln!("warning: the embedded plot font did not load; plot labels will be missing");
        }
    });
}
