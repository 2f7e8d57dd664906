// A 160-frame, 30 fps clip from the 120-frame Bandai walk fixture: its frames, then frames
// 118 … 79 played back (a reflection, as the pipeline pads), so both sides stylize the same text.
export function clip160(text) {
  const [head, motion] = text.split(/^MOTION\r?$/m);
  const lines = motion.split(/\r?\n/).filter((l) => l.trim() !== '');
  const rows = lines.filter((l) => !/^(Frames|Frame Time)/.test(l));
  const frameTime = lines.find((l) => l.startsWith('Frame Time'));
  const out = [...rows];
  for (let i = rows.length - 2; out.length < 160; i--) out.push(rows[i]);
  return `${head}MOTION\nFrames: ${out.length}\n${frameTime}\n${out.join('\n')}\n`;
}
