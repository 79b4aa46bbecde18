//! The window and what lives as long as it: winit's window, the softbuffer surface, egui's
//! winit glue and software rasteriser, and presenting one UI frame into the surface.
//!
//! Presenting composes the eyes into the softbuffer frame (`present.rs`), rasterises the UI
//! over them (`egui_software_backend`) and presents once. Tracing happens only on the worker
//! thread, never while the softbuffer buffer is held.

use std::num::NonZeroU32;
use std::path::PathBuf;
use std::rc::Rc;

use anyhow::Context as _;
use egui_software_backend::{BufferMutRef, ColorFieldOrder, EguiSoftwareRender};
use winit::dpi::{LogicalSize, PhysicalSize};
use winit::event::WindowEvent;
use winit::event_loop::{ActiveEventLoop, EventLoop};

use crate::window::present::{self, Compositor, Look};
use crate::window::syslibs::Backend;
use crate::window::worker::Eyes;

/// The event loop on the chosen backend, with a clear error if the display cannot be opened.
pub fn build_event_loop(backend: Backend) -> anyhow::Result<EventLoop<()>> {
    let mut builder = EventLoop::builder();
    #[cfg(any(
        target_os = "linux",
        target_os = "freebsd",
        target_os = "dragonfly",
        target_os = "netbsd",
        target_os = "openbsd"
    ))]
    match backend {
        Backend::X11 => {
            winit::platform::x11::EventLoopBuilderExtX11::with_x11(&mut builder);
        }
        Backend::Wayland => {
            winit::platform::wayland::EventLoopBuilderExtWayland::with_wayland(&mut builder);
        }
    }
    builder.build().with_context(|| match backend {
        Backend::X11 => format!(
            "cannot open the X11 display {:?} (is the X server running? headless: xvfb-run -a stereotrace)",
            std::env::var("DISPLAY").unwrap_or_default()
        ),
        Backend::Wayland => format!(
            "cannot connect to the Wayland display {:?}; set DISPLAY to use X11 (XWayland) instead",
            std::env::var("WAYLAND_DISPLAY").unwrap_or_default()
        ),
    })
}

/// A window size with both sides non-zero, as softbuffer wants it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Size {
    /// Width, physical pixels.
    pub width: NonZeroU32,
    /// Height, physical pixels.
    pub height: NonZeroU32,
}

impl Size {
    /// The size of a window that is not minimised.
    #[must_use]
    pub fn of(size: PhysicalSize<u32>) -> Option<Self> {
        Some(Self { width: NonZeroU32::new(size.width)?, height: NonZeroU32::new(size.height)? })
    }

    /// (width, height) as plain numbers.
    #[must_use]
    pub fn get(self) -> (u32, u32) {
        (self.width.get(), self.height.get())
    }
}

/// The open window with its surface, egui's glue and the drawing scratch.
pub struct Window {
    /// winit's window.
    winit: Rc<winit::window::Window>,
    surface: softbuffer::Surface<Rc<winit::window::Window>, Rc<winit::window::Window>>,
    egui_winit: egui_winit::State,
    egui_render: EguiSoftwareRender,
    compositor: Compositor,
}

impl Window {
    /// Opens a window titled `title` of `size` logical pixels, with `egui` drawn in it.
    pub fn open(
        event_loop: &ActiveEventLoop,
        title: &str,
        size: LogicalSize<f64>,
        egui: &egui::Context,
    ) -> anyhow::Result<Self> {
        let attrs = winit::window::Window::default_attributes().with_title(title).with_inner_size(size);
        let window = Rc::new(event_loop.create_window(attrs).context("cannot create the window")?);
        let context = softbuffer::Context::new(Rc::clone(&window))
            .map_err(|e| anyhow::anyhow!("cannot start softbuffer: {e}"))?;
        let surface = softbuffer::Surface::new(&context, Rc::clone(&window))
            .map_err(|e| anyhow::anyhow!("cannot create the softbuffer surface: {e}"))?;
        let egui_winit = egui_winit::State::new(
            egui.clone(),
            egui::ViewportId::ROOT,
            &window,
            Some(window.scale_factor() as f32),
            window.theme(),
            None,
        );
        Ok(Self {
            winit: window,
            surface,
            egui_winit,
            egui_render: EguiSoftwareRender::new(ColorFieldOrder::Bgra),
            compositor: Compositor::default(),
        })
    }

    /// The window's inner size, physical pixels.
    #[must_use]
    pub fn inner_size(&self) -> PhysicalSize<u32> {
        self.winit.inner_size()
    }

    /// Whether the window is fullscreen.
    #[must_use]
    pub fn is_fullscreen(&self) -> bool {
        self.winit.fullscreen().is_some()
    }

    /// Borderless fullscreen on the window's monitor, or back to a normal window.
    pub fn set_fullscreen(&self, on: bool) {
        self.winit.set_fullscreen(on.then_some(winit::window::Fullscreen::Borderless(None)));
    }

    /// Sets the window's title.
    pub fn set_title(&self, title: &str) {
        self.winit.set_title(title);
    }

    /// Asks winit for a `RedrawRequested` event.
    pub fn request_redraw(&self) {
        self.winit.request_redraw();
    }

    /// Lets egui see a window event. Its `repaint` hint is not needed: the UI redraws at a
    /// fixed rate (and egui-winit reports `repaint` for `RedrawRequested` itself).
    pub fn on_event(&mut self, event: &WindowEvent) {
        let _ = self.egui_winit.on_window_event(&self.winit, event);
    }

    /// The input egui has gathered since the last UI frame.
    pub fn take_egui_input(&mut self) -> egui::RawInput {
        self.egui_winit.take_egui_input(&self.winit)
    }

    /// Hands egui's platform output (cursor, clipboard, …) to the window.
    pub fn handle_platform_output(&mut self, output: egui::PlatformOutput) {
        self.egui_winit.handle_platform_output(&self.winit, output);
    }

    /// Presents one UI frame of `size`: `frame` as `look` asks, the UI (`ui`, tessellated by
    /// `egui`) over it. Copies the presented pixels into `dump` when given. Returns whether the
    /// eyes were drawn, or `None` when the surface does not match the window yet (a resize in
    /// flight) and the frame was skipped.
    pub fn present(
        &mut self,
        size: Size,
        frame: &Eyes,
        look: Look,
        egui: &egui::Context,
        ui: egui::FullOutput,
        dump: Option<&mut Dump>,
    ) -> anyhow::Result<Option<bool>> {
        let (width, height) = (size.width.get() as usize, size.height.get() as usize);
        self.surface
            .resize(size.width, size.height)
            .map_err(|e| anyhow::anyhow!("cannot resize the frame buffer: {e}"))?;
        let mut buffer = self.surface.buffer_mut().map_err(|e| anyhow::anyhow!("cannot map the frame buffer: {e}"))?;
        if buffer.len() != width * height {
            return Ok(None);
        }
        let eyes = self.compositor.compose(&mut buffer, width, height, frame, look);
        let primitives = egui.tessellate(ui.shapes, ui.pixels_per_point);
        self.egui_render.render(
            &mut BufferMutRef::new(bytemuck::cast_slice_mut(&mut buffer[..]), width, height),
            &primitives,
            &ui.textures_delta,
            ui.pixels_per_point,
        );
        let rows = present::ui_rows(&primitives, ui.pixels_per_point, height);
        present::clear_alpha(&mut buffer[rows.start * width..rows.end * width]);
        if let Some(dump) = dump {
            dump.copy(&buffer, size);
        }
        buffer.present().map_err(|e| anyhow::anyhow!("cannot present the frame: {e}"))?;
        Ok(Some(eyes))
    }
}

/// `--dump`: a copy of the last presented frame, written as a PNG on exit.
#[derive(Debug)]
pub struct Dump {
    path: PathBuf,
    pixels: Vec<u32>,
    size: (u32, u32),
}

impl Dump {
    /// A dump to be written to `path`.
    #[must_use]
    pub fn new(path: PathBuf) -> Self {
        Self { path, pixels: Vec::new(), size: (0, 0) }
    }

    /// Keeps a copy of a presented frame of `size`.
    fn copy(&mut self, pixels: &[u32], size: Size) {
        self.pixels.clear();
        self.pixels.extend_from_slice(pixels);
        self.size = size.get();
    }

    /// Writes the last presented frame.
    pub fn write(&self) -> anyhow::Result<()> {
        if self.pixels.is_empty() {
            anyhow::bail!("no frame was presented, so there is nothing to write to {}", self.path.display());
        }
        viewer::write_png(&self.path, self.size.0, self.size.1, &self.pixels)
    }
}
