// Unit tests of the page's store (src/store.ts) and its typed signals
// (src/signal.ts), in Node without a page or a server: which signals each
// change dispatches, and that an answer older than what is shown is dropped.

import { expect, test } from '@playwright/test';
import type { NodesAnswer, RigInfo, SceneInfo } from '../src/api';
import { Signal } from '../src/signal';
import { Store } from '../src/store';

function scene(over: Partial<SceneInfo> = {}): SceneInfo {
  return {
    revision: 1, path: null, fps: 24, frame: 0, time: 0, range: [0, 0], mode: 'forward', modes: [],
    autoKey: false, canUndo: false, canRedo: false, undo: null, redo: null, selection: [], ...over,
  };
}

function rig(name: string): RigInfo {
  return {
    name, version: '1.0', definition: '', definitionVersion: null, outOfDate: false, editMode: false,
    buildPosition: 0, steps: 0, components: [],
  };
}

const kNodes: NodesAnswer = {
  revision: 1,
  nodes: [
    { uuid: 'u-root', name: 'root', type: 'joint', parent: null },
    { uuid: 'u-hand', name: 'hand', type: 'joint', parent: 'u-root' },
  ],
  controls: [],
};

test.describe('Signal', () => {
  test('calls listeners in the order added, until removed', () => {
    const s = new Signal<number>();
    const seen: string[] = [];
    const removeA = s.add((v) => seen.push(`a${v}`));
    s.add((v) => seen.push(`b${v}`));
    s.dispatch(1);
    removeA();
    s.dispatch(2);
    expect(seen).toEqual(['a1', 'b1', 'b2']);
    expect(s.size).toBe(1);
  });

  test('a listener that throws is reported and the others are still called', () => {
    const reported: unknown[] = [];
    const s = new Signal<string>((e) => reported.push(e));
    const seen: string[] = [];
    s.add(() => {
      throw new Error('broken view');
    });
    s.add((v) => seen.push(v));
    s.dispatch('x');
    expect(seen).toEqual(['x']);
    expect(reported.map((e) => (e as Error).message)).toEqual(['broken view']);
  });

  test('a listener added while dispatching is called from the next dispatch', () => {
    const s = new Signal<number>();
    const seen: number[] = [];
    s.add(() => {
      if (s.size === 1) s.add((v) => seen.push(v));
    });
    s.dispatch(1);
    s.dispatch(2);
    expect(seen).toEqual([2]);
  });
});

test.describe('Store', () => {
  test('a scene fetch dispatches the scene, the selection and the time', () => {
    const store = new Store();
    const got: string[] = [];
    store.signals.sceneChanged.add((s) => got.push(`scene ${s.mode}`));
    store.signals.selectionChanged.add((s) => got.push(`selection ${s.join(',')}`));
    store.signals.timeChanged.add((t) => got.push(`time ${t.frame}`));
    store.setScene(scene({ revision: 7, mode: 'inverse', selection: ['u-hand'], frame: 3 }));
    expect(got).toEqual(['scene inverse', 'selection u-hand', 'time 3']);
    expect(store.knownRevision).toBe(7);
    expect(store.selection).toEqual(['u-hand']);
  });

  test('the answer of a fetch that started before a newer one was shown is dropped', () => {
    const store = new Store();
    let dispatched = 0;
    store.signals.rigsChanged.add(() => dispatched++);
    const older = store.ticket();
    const newer = store.ticket();
    store.setRigs([rig('new')], newer);
    store.setRigs([rig('old')], older);
    expect(store.rigs.map((r) => r.name)).toEqual(['new']);
    expect(dispatched).toBe(1);
    expect(store.stale('rigs', older)).toBe(true);
    expect(store.stale('keys', older)).toBe(false);
  });

  test("a change's answer is newer than a scene fetch still out", () => {
    const store = new Store();
    store.setScene(scene({ selection: [] }));
    const fetch = store.ticket();
    store.setSelection(['u-hand']);
    store.setScene(scene({ selection: [] }), fetch);
    expect(store.selection).toEqual(['u-hand']);
    store.patchScene({ mode: 'body' });
    store.setTime({ frame: 5, time: 5 / 24 });
    expect(store.scene).toMatchObject({ mode: 'body', frame: 5, selection: ['u-hand'] });
  });

  test('poses: an older revision is not shown over a newer one; drags change only their nodes', () => {
    const store = new Store();
    const changes: string[][] = [];
    store.signals.poseChanged.add((m) => changes.push([...m.keys()]));
    const trs = (x: number) => [x, 0, 0, 0, 0, 0, 1, 1, 1, 1] as [number, number, number, number, number, number, number, number, number, number];
    store.applyPose({ revision: 5, nodes: { 'u-root': trs(0), 'u-hand': trs(1) } });
    store.applyPose({ revision: 4, nodes: { 'u-root': trs(9) } });
    store.applyPose({ revision: 6, nodes: { 'u-hand': trs(2) } });
    expect(changes).toEqual([['u-root', 'u-hand'], ['u-hand']]);
    expect(store.pose.get('u-root')![0]).toBe(0);
    expect(store.pose.get('u-hand')![0]).toBe(2);
    expect(store.knownRevision).toBe(6);
    // A new character shows the next pose, whatever its revision (a new server counts again).
    store.setCharacter({ root: {} as never, fileMaterials: new Set(), nodes: kNodes });
    expect(store.pose.size).toBe(0);
    store.applyPose({ revision: 1, nodes: { 'u-root': trs(3) } });
    expect(store.pose.get('u-root')![0]).toBe(3);
  });

  test('a new character renames the nodes', () => {
    const store = new Store();
    let characters = 0;
    store.signals.characterChanged.add(() => characters++);
    store.setCharacter({ root: {} as never, fileMaterials: new Set(), nodes: kNodes });
    expect(characters).toBe(1);
    expect(store.names.get('u-hand')).toBe('hand');
    expect(store.byName.get('root')).toBe('u-root');
  });

  test("keys: the selection's scope, else every character's", () => {
    const store = new Store();
    const scopes: string[] = [];
    store.signals.keysChanged.add((k) => scopes.push(k.scope));
    store.setScene(scene({ keyScopes: { character: 'character' } }));
    store.setKeys(null);
    store.setKeys({ scope: 'controls', frames: [0, 10], times: [0, 10 / 24] });
    expect(store.shownScope()).toBe('controls');
    store.setScene(scene({ keyScopes: { a: 'character', b: 'controls' } }));
    store.setKeys(null);
    expect(scopes).toEqual(['character', 'controls', 'a: character, b: controls']);
    expect(store.keys).toBeNull();
  });
});
