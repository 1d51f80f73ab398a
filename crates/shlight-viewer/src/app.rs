//! The window of `shlight view`: winit events, the wgpu surface, the
//! renderer and the egui overlay, frame by frame.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use shlight_baked::LIGHT_MAX_LMAX;
use shlight_core::encoding::Encoding;
use shlight_core::sh::Window;
use shlight_gpu::wgpu;
use shlight_gpu::{
    Background, GpuContext, Mode, OrbitCamera, Renderer, Scene, Shading, light_renderer,
    scene_renderer,
};
use shlight_io::ToneMap;
use winit::application::ApplicationHandler;
use winit::event::{ElementState, KeyEvent, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::ActiveEventLoop;
use winit::keyboard::{Key, NamedKey};
use winit::window::WindowId;

use crate::controls::{Controls, WINDOWS};
use crate::panel::{PanelInfo, draw_panel};
use crate::screenshot::save_screenshot;
use crate::view_volume::ViewVolume;
use crate::{ViewerError, ViewerOptions};

type Result<T> = std::result::Result<T, ViewerError>;

/// Everything that exists once the window does.
struct Running {
    window: Arc<winit::window::Window>,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    ctx: GpuContext,
    renderer: Renderer,
    depth: wgpu::TextureView,
    egui_state: egui_winit::State,
    egui_renderer: egui_wgpu::Renderer,
}

/// The viewer's state, driven by winit's event loop.
pub struct App<'a> {
    options: &'a ViewerOptions,
    /// The mesh, its transfer and the light (its volume taken out, into
    /// `volume`).
    scene: Scene,
    /// The volume lighting the mesh, the object moving through it.
    volume: Option<ViewVolume>,
    running: Option<Running>,
    controls: Controls,
    orbit: Option<OrbitCamera>,
    dragging: Option<(MouseButton, bool)>,
    shift: bool,
    cursor: Option<(f64, f64)>,
    frames: u32,
    last_frame: Option<Instant>,
    frame_ms: f64,
    /// The encoding (with its SH part's lmax) whose snippet the renderer
    /// holds, and what the panel says of it.
    encoded_for: Option<(Encoding, usize)>,
    encoding_line: String,
    screenshot_requested: bool,
    screenshots_taken: u32,
    message: String,
    pub error: Option<ViewerError>,
}

impl<'a> App<'a> {
    pub fn new(options: &'a ViewerOptions, mut scene: Scene) -> Self {
        let controls = Controls {
            shading: Shading {
                mode: scene.mode,
                lmax: scene.lmax,
                window: Window::None,
                exposure_ev: options.exposure,
                tone_map: Some(options.tone_map),
                albedo: scene.albedo(Mode::Sh),
                background: scene.background,
            },
            env_yaw: 0.0,
            env_pitch: 0.0,
            window_choice: 0,
            encoding: scene.encoding,
            show_panel: !options.hide_panel,
        };
        Self {
            options,
            volume: scene.volume.take().map(ViewVolume::new),
            scene,
            running: None,
            controls,
            orbit: None,
            dragging: None,
            shift: false,
            cursor: None,
            frames: 0,
            last_frame: None,
            frame_ms: 0.0,
            encoded_for: None,
            encoding_line: String::new(),
            screenshot_requested: false,
            screenshots_taken: 0,
            message: String::new(),
            error: None,
        }
    }

    fn start(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
        let (w, h) = self.options.size;
        let window = Arc::new(
            event_loop
                .create_window(
                    winit::window::Window::default_attributes()
                        .with_title("shlight view")
                        .with_inner_size(winit::dpi::PhysicalSize::new(w as u32, h as u32)),
                )
                .map_err(ViewerError::Window)?,
        );
        let instance = shlight_gpu::new_instance(None);
        let surface = instance
            .create_surface(window.clone())
            .map_err(|e| ViewerError::Surface(e.to_string()))?;
        let ctx = GpuContext::with_instance(instance, Some(&surface))?;
        let size = window.inner_size();
        let caps = surface.get_capabilities(&ctx.adapter);
        let format = caps
            .formats
            .iter()
            .copied()
            .find(|f| f.is_srgb())
            .or_else(|| caps.formats.first().copied())
            .ok_or(ViewerError::NoSurfaceFormat)?;
        let mut config = surface
            .get_default_config(&ctx.adapter, size.width.max(1), size.height.max(1))
            .ok_or_else(|| ViewerError::SurfaceAdapter(ctx.adapter_name()))?;
        config.format = format;
        config.present_mode = wgpu::PresentMode::AutoNoVsync;
        config.view_formats = vec![];
        surface.configure(&ctx.device, &config);
        let scene = &self.scene;
        let renderer = match &mut self.volume {
            // The mesh is drawn by the volume pass, lit by its probes.
            Some(v) => {
                v.start(&ctx, format, scene.geometry(), scene.albedo(Mode::Sh))?;
                light_renderer(&ctx, format, &scene.light)
            }
            None => scene_renderer(&ctx, format, scene)?,
        };
        let depth = shlight_gpu::depth_view(&ctx, config.width, config.height);
        let egui_ctx = egui::Context::default();
        let egui_state = egui_winit::State::new(
            egui_ctx,
            egui::ViewportId::ROOT,
            &window,
            Some(window.scale_factor() as f32),
            None,
            Some(ctx.device.limits().max_texture_dimension_2d as usize),
        );
        let egui_renderer = egui_wgpu::Renderer::new(&ctx.device, format, Default::default());
        self.orbit = Some(OrbitCamera::new(
            self.scene.mesh.bounds(),
            config.width as f32 / config.height as f32,
        ));
        self.message = ctx.adapter_name();
        self.running = Some(Running {
            window,
            surface,
            config,
            ctx,
            renderer,
            depth,
            egui_state,
            egui_renderer,
        });
        Ok(())
    }

    fn resize(&mut self, width: u32, height: u32) {
        if let Some(r) = &mut self.running
            && width > 0
            && height > 0
        {
            r.config.width = width;
            r.config.height = height;
            r.surface.configure(&r.ctx.device, &r.config);
            r.depth = shlight_gpu::depth_view(&r.ctx, width, height);
        }
    }

    /// One frame: the overlay, the light turned by the environment
    /// rotation, the scene and the overlay drawn; a screenshot when asked.
    fn redraw(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
        let now = Instant::now();
        if let Some(last) = self.last_frame {
            let ms = (now - last).as_secs_f64() * 1e3;
            self.frame_ms = if self.frame_ms == 0.0 {
                ms
            } else {
                0.9 * self.frame_ms + 0.1 * ms
            };
        }
        self.last_frame = Some(now);
        self.controls.shading.window = self.controls.window();
        let rotation = self.controls.rotation();
        let rotated = self.scene.turned_radiance(rotation);
        let Some(r) = self.running.as_mut() else {
            return Ok(());
        };
        r.renderer.set_light(&r.ctx, &rotated);
        r.renderer.set_environment_rotation(rotation);
        if let Some(v) = &mut self.volume {
            v.relight(&r.ctx, &rotated)?;
        }
        let shading = self.shading_to_draw()?;
        let Some(r) = self.running.as_mut() else {
            return Ok(());
        };
        let volume_lines = self
            .volume
            .as_ref()
            .map_or_else(Vec::new, ViewVolume::panel_lines);

        let raw_input = r.egui_state.take_egui_input(&r.window);
        let egui_ctx = r.egui_state.egui_ctx().clone();
        let panel = PanelInfo {
            fps: if self.frame_ms > 0.0 {
                1e3 / self.frame_ms
            } else {
                0.0
            },
            frame_ms: self.frame_ms,
            adapter: &self.message,
            coefficients: &rotated,
            has_map: self.scene.light.map.is_some(),
            prt: self.scene.transfer.as_ref().map(|t| t.mode.as_str()),
            volume: &volume_lines,
            encoding: &self.encoding_line,
        };
        let controls = &mut self.controls;
        let mut screenshot = false;
        let full = egui_ctx.run_ui(raw_input, |ui| {
            if controls.show_panel {
                screenshot |= draw_panel(ui.ctx(), controls, &panel);
            }
        });
        self.screenshot_requested |= screenshot;
        r.egui_state
            .handle_platform_output(&r.window, full.platform_output);
        let jobs = egui_ctx.tessellate(full.shapes, full.pixels_per_point);
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [r.config.width, r.config.height],
            pixels_per_point: full.pixels_per_point,
        };
        for (id, deltas) in &full.textures_delta.set {
            for delta in deltas {
                r.egui_renderer
                    .update_texture(&r.ctx.device, &r.ctx.queue, *id, delta);
            }
        }

        let last_scripted = self
            .options
            .screenshot
            .as_ref()
            .filter(|_| self.frames + 1 >= self.options.frames);
        let capture = last_scripted.is_some() || self.screenshot_requested;
        let frame = match r.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t)
            | wgpu::CurrentSurfaceTexture::Suboptimal(t) => t,
            _ => {
                // Lost, outdated or timed out: reconfigure and try next frame.
                r.surface.configure(&r.ctx.device, &r.config);
                return Ok(());
            }
        };
        let target_view = frame.texture.create_view(&Default::default());
        // A screenshot renders the same frame into a copyable texture too.
        let capture_target = capture.then(|| {
            r.ctx.device.create_texture(&wgpu::TextureDescriptor {
                label: Some("screenshot"),
                size: frame.texture.size(),
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: r.config.format,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
                view_formats: &[],
            })
        });
        let camera = self.orbit.expect("set with the window").camera();
        let aspect = r.config.width as f32 / r.config.height as f32;
        let mut encoder = r.ctx.device.create_command_encoder(&Default::default());
        let mut views = vec![target_view];
        if let Some(t) = &capture_target {
            views.push(t.create_view(&Default::default()));
        }
        // The overlay's buffers are the same for every target: upload once.
        let extra = r.egui_renderer.update_buffers(
            &r.ctx.device,
            &r.ctx.queue,
            &mut encoder,
            &jobs,
            &screen,
        );
        for view in &views {
            r.renderer.draw(
                &r.ctx,
                &mut encoder,
                view,
                &r.depth,
                &camera,
                aspect,
                &shading,
            )?;
            if let Some(v) = &self.volume {
                v.draw(
                    &r.ctx,
                    &mut encoder,
                    view,
                    &r.depth,
                    &camera,
                    aspect,
                    &self.controls.shading,
                );
            }
            let pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("overlay"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Load,
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            r.egui_renderer
                .render(&mut pass.forget_lifetime(), &jobs, &screen);
        }
        r.ctx
            .queue
            .submit(extra.into_iter().chain([encoder.finish()]));
        for id in &full.textures_delta.free {
            r.egui_renderer.free_texture(id);
        }
        if let Some(texture) = capture_target {
            let path = match last_scripted {
                Some(p) => p.clone(),
                None => {
                    self.screenshots_taken += 1;
                    PathBuf::from(format!("shlight-view-{}.png", self.screenshots_taken))
                }
            };
            save_screenshot(&r.ctx, &texture, &path)?;
            self.screenshot_requested = false;
            if last_scripted.is_none() {
                eprintln!("saved {}", path.display());
            }
        }
        r.window.pre_present_notify();
        r.ctx.queue.present(frame);
        self.frames += 1;
        if last_scripted.is_some() {
            event_loop.exit();
        }
        Ok(())
    }

    fn key(&mut self, event: &KeyEvent, event_loop: &ActiveEventLoop) {
        if event.state != ElementState::Pressed {
            return;
        }
        if let Key::Character(s) = &event.logical_key
            && let (Some(v), Some(r)) = (&mut self.volume, &self.running)
            && v.key(&r.ctx, s.as_str())
        {
            return;
        }
        let c = &mut self.controls;
        match &event.logical_key {
            Key::Named(NamedKey::Escape) => event_loop.exit(),
            Key::Named(NamedKey::ArrowLeft) => c.env_yaw -= 0.1,
            Key::Named(NamedKey::ArrowRight) => c.env_yaw += 0.1,
            Key::Named(NamedKey::ArrowUp) => c.env_pitch -= 0.1,
            Key::Named(NamedKey::ArrowDown) => c.env_pitch += 0.1,
            Key::Character(s) => match s.as_str() {
                "q" => event_loop.exit(),
                "m" => {
                    c.shading.mode = match c.shading.mode {
                        Mode::Sh if self.scene.transfer.is_some() => Mode::Prt,
                        Mode::Sh | Mode::Prt => Mode::Normals,
                        Mode::Normals | Mode::Encoded => Mode::Sh,
                    }
                }
                "b" => {
                    c.shading.background = match c.shading.background {
                        Background::None if self.scene.light.map.is_some() => Background::Map,
                        Background::None | Background::Map => Background::Sh,
                        Background::Sh => Background::None,
                    }
                }
                "w" => c.window_choice = (c.window_choice + 1) % WINDOWS.len(),
                "e" => {
                    c.encoding =
                        Controls::next_encoding(c.encoding, self.scene.light.map.is_some());
                }
                "t" => {
                    let next = match c.shading.tone_map {
                        Some(ToneMap::Clamp) => ToneMap::Reinhard,
                        Some(ToneMap::Reinhard) => ToneMap::Aces,
                        _ => ToneMap::Clamp,
                    };
                    c.shading.tone_map = Some(next);
                }
                "+" | "=" => c.shading.exposure_ev += 0.5,
                "-" => c.shading.exposure_ev -= 0.5,
                "p" => self.screenshot_requested = true,
                "h" => c.show_panel = !c.show_panel,
                digit => {
                    if let Ok(l) = digit.parse::<usize>()
                        && l <= LIGHT_MAX_LMAX
                    {
                        c.shading.lmax = l;
                    }
                }
            },
            _ => {}
        }
    }

    /// The shading the renderer draws: the controls', in encoded mode when
    /// SH mode shows an encoding other than plain SH, whose snippet is
    /// built (and its pipeline compiled) when the encoding or, for those
    /// with an SH part, the lmax changed.
    fn shading_to_draw(&mut self) -> Result<Shading> {
        let mut shading = self.controls.shading;
        if shading.mode == Mode::Prt {
            // A glossy file's diffuse base: none (the glossy layer alone)
            // unless the scene's albedo gives one, as in a headless frame.
            shading.albedo = self.scene.albedo(Mode::Prt);
        }
        let encoding = self.controls.encoding;
        if shading.mode != Mode::Sh || encoding == Encoding::Sh || self.volume.is_some() {
            return Ok(shading);
        }
        let Some(r) = self.running.as_mut() else {
            return Ok(shading);
        };
        let lmax = if encoding.takes_lmax() {
            shading.lmax
        } else {
            0
        };
        if self.encoded_for != Some((encoding, lmax)) {
            let started = Instant::now();
            let (encoded, snippet) = self.scene.light.encoded_light(encoding, lmax)?;
            r.renderer.set_encoding(&r.ctx, &snippet)?;
            let lights = match encoding {
                Encoding::DominantSh | Encoding::SloanSh => {
                    format!(", {} light(s)", encoded.lights().len())
                }
                _ => String::new(),
            };
            self.encoding_line = format!(
                "{encoding}: {} floats{lights}; encoded and compiled in {:.0} ms",
                encoded.floats(encoding),
                started.elapsed().as_secs_f64() * 1e3
            );
            self.encoded_for = Some((encoding, lmax));
        }
        shading.mode = Mode::Encoded;
        Ok(shading)
    }

    fn drag(&mut self, x: f64, y: f64) {
        let Some((px, py)) = self.cursor.replace((x, y)) else {
            return;
        };
        let (dx, dy) = ((x - px) as f32, (y - py) as f32);
        match self.dragging {
            Some((MouseButton::Left, false)) => {
                if let Some(o) = &mut self.orbit {
                    o.yaw -= dx * 0.01;
                    o.pitch = (o.pitch + dy * 0.01).clamp(-1.5, 1.5);
                }
            }
            Some(_) => {
                self.controls.env_yaw += f64::from(dx) * 0.01;
                self.controls.env_pitch += f64::from(dy) * 0.01;
            }
            None => {}
        }
    }
}

impl ApplicationHandler for App<'_> {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.running.is_none()
            && let Err(e) = self.start(event_loop)
        {
            self.error = Some(e);
            event_loop.exit();
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        let consumed = match &mut self.running {
            Some(r) => r.egui_state.on_window_event(&r.window, &event).consumed,
            None => false,
        };
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => self.resize(size.width, size.height),
            WindowEvent::RedrawRequested => {
                if let Err(e) = self.redraw(event_loop) {
                    self.error = Some(e);
                    event_loop.exit();
                }
            }
            WindowEvent::ModifiersChanged(m) => self.shift = m.state().shift_key(),
            WindowEvent::KeyboardInput { event, .. } if !consumed => self.key(&event, event_loop),
            WindowEvent::MouseInput { state, button, .. } => match state {
                ElementState::Pressed if !consumed => {
                    self.dragging = Some((button, self.shift));
                }
                _ => self.dragging = None,
            },
            WindowEvent::CursorMoved { position, .. } => self.drag(position.x, position.y),
            WindowEvent::MouseWheel { delta, .. } if !consumed => {
                let lines = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => p.y as f32 / 40.0,
                };
                if let Some(o) = &mut self.orbit {
                    o.distance = (o.distance * 0.9f32.powf(lines)).max(o.radius * 0.2);
                }
            }
            _ => {}
        }
    }

    fn about_to_wait(&mut self, _: &ActiveEventLoop) {
        if let Some(r) = &self.running {
            r.window.request_redraw();
        }
    }
}
