"""Derive the canonical rig's T-pose offsets and the Bandai rig's reference (standing) pose.

Run once by hand: python3 tools/bandai_reference.py DATA/dataset-2/data/dataset-2_walk_normal_001.bvh
It prints Rust constants pasted into src/skeleton/canonical.rs and src/skeleton/rigs.rs. Kept so the
numbers can be regenerated; nothing at build or run time depends on it (needs numpy, scipy).
"""
import sys, numpy as np
from scipy.spatial.transform import Rotation as R

def parse(path):
    names, parents, offsets, chans = [], [], [], []
    stack, lines = [], open(path).read().split('\n')
    i = 0
    while not lines[i].strip().startswith('MOTION'):
        t = lines[i].split()
        if t and t[0] in ('ROOT', 'JOINT'):
            names.append(t[1]); parents.append(stack[-1] if stack else -1)
        elif t and t[0] == 'End':
            names.append(None); parents.append(stack[-1])
        elif t and t[0] == '{':
            stack.append(len(names) - 1)
        elif t and t[0] == '}':
            stack.pop()
        elif t and t[0] == 'OFFSET':
            offsets.append([float(x) for x in t[1:4]])
        elif t and t[0] == 'CHANNELS':
            chans.append(t[2:])
        i += 1
    data = np.array([[float(x) for x in l.split()] for l in lines[i + 3:] if l.strip()])
    return names, parents, np.array(offsets), chans, data

names, parents, offsets, chans, data = parse(sys.argv[1])
frame = data[0]
joints = [k for k, n in enumerate(names) if n is not None]
glob_r, glob_p, loc_r = {}, {}, {}
c = 0
for k in joints:
    ch = chans[joints.index(k)]
    v = frame[c:c + len(ch)]; c += len(ch)
    pos = offsets[k].copy()
    rot = R.identity()
    for name, x in zip(ch, v):
        if name.endswith('position'):
            pos['XYZ'.index(name[0])] = x
        else:
            rot = rot * R.from_euler(name[0].lower(), x, degrees=True)
    p = parents[k]
    loc_r[k] = rot
    if p == -1:
        glob_r[k], glob_p[k] = rot, pos
    else:
        glob_r[k] = glob_r[p] * rot
        glob_p[k] = glob_p[p] + glob_r[p].apply(pos)

idx = {names[k]: k for k in joints}
left = glob_p[idx['UpperLeg_L']] - glob_p[idx['UpperLeg_R']] + glob_p[idx['Shoulder_L']] - glob_p[idx['Shoulder_R']]
left[1] = 0; left /= np.linalg.norm(left)
fwd = np.cross(left, [0, 1, 0])
yaw = np.arctan2(fwd[0], fwd[2])
unyaw = R.from_euler('y', -yaw)
canon = [n for n in names if n is not None and n != 'joint_Root']
print('# facing yaw (deg)', np.degrees(yaw))
print('// world offsets of the reference standing frame, facing +Z')
for n in canon:
    k = idx[n]; p = parents[k]
    off = unyaw.apply(glob_p[k] - glob_p[p]) if names[p] != 'joint_Root' else np.zeros(3)
    print(f'    ("{n}", [{off[0]:.4f}, {off[1]:.4f}, {off[2]:.4f}]),')
print('// Bandai reference pose: local rotations (x, y, z, w); Hips without its yaw')
for n in canon:
    k = idx[n]
    q = (unyaw * glob_r[k]).as_quat() if n == 'Hips' else loc_r[k].as_quat()
    print(f'    [{q[0]:.6f}, {q[1]:.6f}, {q[2]:.6f}, {q[3]:.6f}], // {n}')
