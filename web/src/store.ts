// The page's state: what the server last said about the scene (its
// summary, the node set and controls, the selection, the pose, the time,
// the keys of the selection, the rigs) and the revision this tab has seen.
// Views never get state pushed into them: they subscribe to the store's
// named signals (as three.js's editor: `editor.signals.objectSelected`,
// the viewport adding its listener) and render from the store.
//
// Only the setters below change the state, and each dispatches the signals
// of what it changed. The fetches that feed them (and which answers are too
// old to show) are app.ts's.

import type * as THREE from 'three';
import type { KeysAnswer, NodesAnswer, PoseAnswer, RigInfo, SceneInfo, Trs } from './api';
import { Signal } from './signal';

/** The character as the viewport draws it: the glTF's scene and the node list it was loaded with. */
export interface Character {
  /** The glTF's scene; every object with `userData.uuid` is a rigel node. */
  root: THREE.Group;
  /** Materials the file defines (drawn as the file says; the others are GLTFLoader's default). */
  fileMaterials: ReadonlySet<THREE.Material>;
  nodes: NodesAnswer;
}

export interface Time {
  frame: number;
  time: number;
}

export interface Keys {
  /** The selection's keys (null: nothing selected). */
  keys: KeysAnswer | null;
  /** The keying scope shown: the selection's, or with nothing selected every character's. */
  scope: string;
}

/** The parts whose fetches are ordered by tickets. */
export type Part = 'scene' | 'nodes' | 'rigs' | 'keys';

export class Store {
  /** The scene summary of GET /api/scene, kept current by the answers of this tab's changes. */
  scene: SceneInfo | null = null;
  /** The node list and controls (replaced, never merged). */
  nodes: NodesAnswer | null = null;
  character: Character | null = null;
  /** Local TRS of every node shown, by uuid (drags update only the nodes they moved). */
  readonly pose = new Map<string, Trs>();
  rigs: RigInfo[] = [];
  keys: KeysAnswer | null = null;
  scope = '';
  /** uuid -> name and name -> uuid of every node of the character. */
  readonly names = new Map<string, string>();
  readonly byName = new Map<string, string>();
  /** The newest revision this tab knows it has seen (its own or fetched). */
  knownRevision = -1;
  /** The revision of the pose shown (an older answer is not shown over it). */
  private poseRevision = -1;
  // Every fetch takes a ticket when it starts; an answer older than what a
  // part shows (a fetch that started earlier and came back later, or one
  // that started before a change's answer was applied) is dropped.
  private tickets = 0;
  private readonly shown: Record<Part, number> = { scene: 0, nodes: 0, rigs: 0, keys: 0 };

  readonly signals: {
    /** The scene summary changed (mode, options, undo/redo, range, ...). */
    sceneChanged: Signal<SceneInfo>;
    selectionChanged: Signal<readonly string[]>;
    timeChanged: Signal<Time>;
    /** A new node set and glTF (a rig added or removed, shapes changed). */
    characterChanged: Signal<Character>;
    /** The node list was read again (changed or not). */
    nodesChanged: Signal<NodesAnswer>;
    /** Local TRS of the nodes whose pose changed. */
    poseChanged: Signal<ReadonlyMap<string, Trs>>;
    rigsChanged: Signal<readonly RigInfo[]>;
    keysChanged: Signal<Keys>;
  };

  /** `report` gets what a subscriber throws (the status bar's `caught`). */
  constructor(report: (e: unknown) => void = (e) => console.error(e)) {
    this.signals = {
      sceneChanged: new Signal(report),
      selectionChanged: new Signal(report),
      timeChanged: new Signal(report),
      characterChanged: new Signal(report),
      nodesChanged: new Signal(report),
      poseChanged: new Signal(report),
      rigsChanged: new Signal(report),
      keysChanged: new Signal(report),
    };
  }

  get selection(): readonly string[] {
    return this.scene?.selection ?? [];
  }

  /** A ticket for a fetch starting now. */
  ticket(): number {
    return ++this.tickets;
  }

  /** True when `part` already shows what a fetch or change later than `ticket` said. */
  stale(part: Part, ticket: number): boolean {
    return ticket < this.shown[part];
  }

  /** Takes the answer of the fetch of `ticket` for `part`, unless it is stale. */
  private accept(part: Part, ticket: number): boolean {
    if (this.stale(part, ticket)) return false;
    this.shown[part] = ticket;
    return true;
  }

  noteRevision(revision: number): void {
    if (revision > this.knownRevision) this.knownRevision = revision;
  }

  /** A fresh scene summary (GET /api/scene): every part of it may have changed. */
  setScene(scene: SceneInfo, ticket = this.ticket()): void {
    if (!this.accept('scene', ticket)) return;
    this.scene = scene;
    this.noteRevision(scene.revision);
    this.signals.sceneChanged.dispatch(scene);
    this.signals.selectionChanged.dispatch(scene.selection);
    this.signals.timeChanged.dispatch({ frame: scene.frame, time: scene.time });
  }

  /** What the answer of a change said about the scene (mode, options). */
  // The answers of changes below are newer than any scene fetch still out.
  patchScene(patch: Partial<Pick<SceneInfo, 'mode' | 'autoKey' | 'playbackRange'>>): void {
    this.accept('scene', this.ticket());
    if (this.scene) Object.assign(this.scene, patch);
    if (this.scene) this.signals.sceneChanged.dispatch(this.scene);
  }

  setSelection(selection: string[]): void {
    this.accept('scene', this.ticket());
    if (this.scene) this.scene.selection = selection;
    this.signals.selectionChanged.dispatch(selection);
  }

  setTime(time: Time): void {
    this.accept('scene', this.ticket());
    if (this.scene) {
      this.scene.frame = time.frame;
      this.scene.time = time.time;
    }
    this.signals.timeChanged.dispatch(time);
  }

  /** A new character: names follow it, and the next pose of any revision is shown in full. */
  setCharacter(character: Character): void {
    this.character = character;
    this.names.clear();
    this.byName.clear();
    for (const x of character.nodes.nodes) {
      this.names.set(x.uuid, x.name);
      this.byName.set(x.name, x.uuid);
    }
    this.pose.clear();
    this.poseRevision = -1;
    this.signals.characterChanged.dispatch(character);
  }

  /** The node list of the fetch of `ticket` (the caller checked `stale` before loading its glTF). */
  setNodes(nodes: NodesAnswer, ticket = this.ticket()): void {
    if (!this.accept('nodes', ticket)) return;
    this.nodes = nodes;
    this.signals.nodesChanged.dispatch(nodes);
  }

  /** Forgets the pose's revision (a new server may count revisions again from 0). */
  resetRevisions(revision: number): void {
    this.knownRevision = revision;
    this.poseRevision = -1;
  }

  /** Shows a pose (whole or the nodes a drag moved) unless a newer one is already shown. */
  applyPose(pose: PoseAnswer): void {
    if (typeof pose.revision === 'number') {
      if (pose.revision < this.poseRevision) return;
      this.poseRevision = pose.revision;
      this.noteRevision(pose.revision);
    }
    const changed = new Map<string, Trs>();
    for (const uuid in pose.nodes) {
      const trs = pose.nodes[uuid]!;
      this.pose.set(uuid, trs);
      changed.set(uuid, trs);
    }
    this.signals.poseChanged.dispatch(changed);
  }

  setRigs(rigs: RigInfo[], ticket = this.ticket()): void {
    if (!this.accept('rigs', ticket)) return;
    this.rigs = rigs;
    this.signals.rigsChanged.dispatch(rigs);
  }

  /** The selection's keys, or with nothing selected (null) the scopes of the characters. */
  setKeys(keys: KeysAnswer | null, ticket = this.ticket()): void {
    if (!this.accept('keys', ticket)) return;
    this.keys = keys;
    if (keys) {
      this.scope = keys.scope ?? '';
    } else {
      // Nothing selected: the scopes of the characters (one line per rig).
      const scopes = this.scene?.keyScopes ?? {};
      const names = Object.keys(scopes);
      this.scope = names.length === 1 ? scopes[names[0]!]! : names.map((x) => `${x}: ${scopes[x]}`).join(', ');
    }
    this.signals.keysChanged.dispatch({ keys, scope: this.scope });
  }

  /** The keying scope to show (the selection's keys', else the characters'). */
  shownScope(): string {
    return this.keys?.scope ?? this.scope;
  }
}
