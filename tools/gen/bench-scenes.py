#!/usr/bin/env python3
"""Writes the benchmark scenes of tools/bench-suite.sh into OUT_DIR, with absolute paths:
  synth-{dvr,iso,slice}.json   the 256^3 synthetic volume (issue 4), DVR, iso 0.5, three slices
  echam5-{dvr,iso,slice}.json  the ECHAM5 temperature volume (needs the netCDF file), iso 260 K
  peer-{dvr,iso}.json          the VTK peer's volume scenes
  train-N.json                 N wagons along the train track over the FMV valley (N = 0: the model
                               hidden), overview camera, 100 s into the run (issue 7)
  train-anim-N.json            the same with animated wagons (wagon-animated.gltf, written here by
                               tools/gen/make-wagon.py --animated: node channels and a skin), N = 1, 100, 1000
usage: bench-scenes.py OUT_DIR [--echam5 FILE.nc] [--dem FILE.tif]"""
import argparse, copy, json, os, subprocess, sys

root = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..'))
ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
ap.add_argument('out')
ap.add_argument('--echam5', default=os.path.join(root, '..', 'shared', 'data', 'netcdf', 'echam5_rectilinear_grid_3D.nc'))
ap.add_argument('--dem', default=os.path.join(root, 'assets', 'generated', 'fmv', 'flight-dem.tif'))
args = ap.parse_args()
os.makedirs(args.out, exist_ok=True)

def load(rel):
    with open(os.path.join(root, 'assets', 'scenes', rel)) as f:
        return json.load(f)

def save(name, scene):
    with open(os.path.join(args.out, name), 'w') as f:
        json.dump(scene, f, indent=1)

def volume(scene):
    return next(l for l in scene['layers'] if l['type'] == 'volume')

def variants(base, prefix, iso, slices):
    save(prefix + '-dvr.json', base)
    s = copy.deepcopy(base)
    volume(s).update({'mode': ['iso'], 'isovalues': [iso]})
    save(prefix + '-iso.json', s)
    s = copy.deepcopy(base)
    volume(s).update({'mode': ['slice'], 'slices': slices})
    save(prefix + '-slice.json', s)

variants(load('volume-synthetic.json'), 'synth', 0.5, [{'lon': 0}, {'lat': 50}, {'height': 400000}])
if os.path.exists(args.echam5):
    e = load('echam5.json')
    volume(e)['path'] = os.path.abspath(args.echam5)
    variants(e, 'echam5', 260, [{'lon': 10}, {'lat': 30}, {'height': 5000}])
save('peer-dvr.json', load('volume-peer.json'))
save('peer-iso.json', load('volume-peer-iso.json'))

train = load('train.json')
train['layers'][0]['elevation'] = [os.path.abspath(args.dem)]
model = train['layers'][1]
model['file'] = os.path.join(root, 'assets', 'models', 'wagon.gltf')
model['trajectory']['file'] = os.path.join(root, 'assets', 'scenes', 'train-track.csv')
train['camera'] = {'mode': 'overview', 'target': 'Train'}
train['time'] = {'start': '2026-06-21T09:00:00Z', 'end': '2026-06-21T09:05:00Z',
                 'current': '2026-06-21T09:01:40Z', 'rate': 1, 'playing': True}
for n in (0, 1, 100, 1000):
    s = copy.deepcopy(train)
    s['layers'][1]['copies'] = {'count': max(n, 1), 'spacing': 100.0 / max(n, 1)}  # over 100 s of track
    if n == 0:
        s['layers'][1]['visible'] = False   # same camera, nothing drawn: the terrain's cost alone
    save('train-%d.json' % n, s)

animated = os.path.join(os.path.abspath(args.out), 'wagon-animated.gltf')
subprocess.run([sys.executable, os.path.join(root, 'tools', 'gen', 'make-wagon.py'), animated, '--animated'], check=True)
for n in (1, 100, 1000):
    s = copy.deepcopy(train)
    s['layers'][1]['file'] = animated
    s['layers'][1]['copies'] = {'count': n, 'spacing': 100.0 / n}
    save('train-anim-%d.json' % n, s)
