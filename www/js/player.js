// The playback clock: time in seconds, play/pause, speed, loop; calls onTime on every animation
// frame while playing and on every seek.

export class Player {
  constructor(onTime) {
    this.onTime = onTime;
    this.time = 0;
    this.duration = 0;
    this.speed = 1;
    this.loop = true;
    this.playing = true;
    this.last = null;
    this.onState = () => {};
    requestAnimationFrame((t) => this.tick(t));
  }

  tick(now) {
    if (this.playing && this.duration > 0 && this.last != null) {
      let t = this.time + ((now - this.last) / 1000) * this.speed;
      if (t >= this.duration) {
        if (this.loop) t %= this.duration;
        else {
          t = this.duration;
          this.setPlaying(false);
        }
      }
      this.time = t;
      this.onTime(t);
    }
    this.last = now;
    requestAnimationFrame((t) => this.tick(t));
  }

  setPlaying(playing) {
    if (playing && this.time >= this.duration) this.time = 0;
    this.playing = playing;
    this.onState(playing);
  }

  seek(time) {
    this.time = Math.max(0, Math.min(this.duration, time));
    this.onTime(this.time);
  }

  setDuration(duration) {
    this.duration = duration;
    if (this.time > duration) this.time = 0;
    this.onTime(this.time);
  }
}
