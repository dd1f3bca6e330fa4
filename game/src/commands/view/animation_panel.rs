//! The panel's "Animation" section: the clips of every animation player (a glTF file's),
//! which one plays, pause, speed, looping and the clip's time.

use lumen::prelude::*;

/// Draws one block per [`AnimationPlayer`] in `world`; changes apply to the next frame.
pub fn animation_ui(ui: &mut egui::Ui, world: &mut World) {
    let mut players = world.query::<&mut AnimationPlayer>();
    for (k, mut player) in players.iter_mut(world).enumerate() {
        ui.push_id(k, |ui| player_ui(ui, &mut player));
    }
}

/// A clip as the panel lists it: its name and duration.
fn clip_label(clip: &lumen::scene::AnimationClip) -> String {
    format!("{} ({:.2} s)", clip.name, clip.duration_s)
}

/// One line per [`AnimationPlayer`] in `world`, printed when the viewer opens a scene:
/// the clip it plays (or holds) and every clip the panel lists.
pub fn animation_lines(world: &mut World) -> Vec<String> {
    let mut players = world.query::<&AnimationPlayer>();
    players
        .iter(world)
        .filter_map(|player| {
            let current = player.clips().get(player.current()?)?;
            let state = if player.is_paused() {
                format!("is held at {:.2} s", player.time_s())
            } else {
                "plays".to_string()
            };
            let clips: Vec<String> = player.clips().iter().map(|c| clip_label(c)).collect();
            Some(format!(
                "animation '{}' {state} (clips: {})",
                current.name,
                clips.join(", ")
            ))
        })
        .collect()
}

fn player_ui(ui: &mut egui::Ui, player: &mut AnimationPlayer) {
    let clips: Vec<String> = player.clips().iter().map(|c| clip_label(c)).collect();
    let mut chosen = None;
    for (i, label) in clips.into_iter().enumerate() {
        if ui
            .selectable_label(player.current() == Some(i), label)
            .clicked()
        {
            chosen = Some(i);
        }
    }
    if let Some(i) = chosen {
        // The index comes from the list just drawn.
        let _ = player.play(i);
    }
    ui.horizontal(|ui| {
        let paused = player.is_paused();
        if ui.button(if paused { "play" } else { "pause" }).clicked() {
            if paused {
                player.resume();
            } else {
                player.pause();
            }
        }
        let duration = player
            .current()
            .and_then(|i| player.clips().get(i))
            .map_or(0.0, |c| c.duration_s);
        let mut t = player.time_s();
        if ui
            .add(egui::Slider::new(&mut t, 0.0..=duration.max(1e-3)).suffix(" s"))
            .changed()
        {
            player.seek(t);
        }
    });
    let mut speed = player.speed();
    if ui
        .add(egui::Slider::new(&mut speed, -2.0..=4.0).text("speed"))
        .changed()
    {
        player.set_speed(speed);
    }
    let mut looping = player.is_looping();
    if ui.checkbox(&mut looping, "loop").changed() {
        player.set_looping(looping);
    }
}
