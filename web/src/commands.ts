// The changes a user makes, as commands (three.js's editor runs every edit
// as a Command through `editor.execute`): each sends one request of api.ts,
// puts what its answer says into the store, says what the status bar
// shows, and names what the change can affect, which App.execute re-reads
// after it. Undo and redo are the server's (one history for every client),
// so a command needs no undo of its own here.

import { ApiError } from './api';
import type {
  Api,
  BuildAnswer,
  BuildGraphJson,
  GraphBuildAnswer,
  GraphSaveAnswer,
  ChannelKeysAnswer,
  ChannelValuesAnswer,
  CurveKeysAnswer,
  CurveKeysRequest,
  SelectionSetRequest,
  SelectionSetsAnswer,
  HistoryAnswer,
  KeyAnswer,
  ModeAnswer,
  OptionsAnswer,
  Revised,
  RigAddAnswer,
  RigEditAnswer,
  RigEditModeAnswer,
  RigFeatureAnswer,
  RigJson,
  RigUpdateAnswer,
  SaveDefinitionAnswer,
  SelectAnswer,
  StepAnswer,
  TimeAnswer,
} from './api';
import type { Store } from './store';

/**
 * What a change can affect: re-read after it. `everything` is a change of
 * the node set (a rig built, rebuilt or removed, an undo that may be any of
 * those): everything is read again, one such refresh at a time.
 */
export type Reread = 'scene' | 'pose' | 'keys' | 'rigs' | 'everything';

export interface Command<A> {
  /** Sends the request (a failure is reported by the client and rejects). */
  send(api: Api): Promise<A>;
  /** Puts what the answer says into the store, before anything is re-read. */
  apply?(answer: A, store: Store): void;
  /** What the status bar says once it succeeded (nothing: an error shown is only cleared). */
  message?(answer: A, store: Store): string;
  affects: readonly Reread[];
}

/** `base` with `extra` added to its `apply` (a panel's own state from the answer). */
export function also<A>(base: Command<A>, extra: (answer: A) => void): Command<A> {
  return {
    ...base,
    apply: (a, store) => {
      base.apply?.(a, store);
      extra(a);
    },
  };
}

/**
 * Runs a build (a definition's or a graph's) through `execute`: `done` with
 * its answer; a failure of the build itself (not of reading the scene again
 * after it) goes to `failed` with the error's message (the server's, for an
 * API error) and is thrown again.
 */
export async function runBuild<A>(
  execute: (c: Command<A>) => Promise<A>,
  command: Command<A>,
  done: (answer: A) => void,
  failed: (message: string, reason: string) => void,
): Promise<void> {
  let built = false;
  try {
    await execute(
      also(command, (a) => {
        built = true;
        done(a);
      }),
    );
  } catch (e) {
    if (built) throw e;
    const message = e instanceof Error ? e.message : String(e);
    failed(message, e instanceof ApiError ? e.message : message);
    throw e;
  }
}

// ------------------------------------------------------------------ posing

export function select(controls: string[], add: boolean): Command<SelectAnswer> {
  return {
    send: (api) => api.select({ controls, add }),
    apply: (a, store) => store.setSelection(a.selection),
    affects: ['keys'],
  };
}

export function setMode(mode: string): Command<ModeAnswer> {
  return {
    send: (api) => api.mode(mode),
    apply: (a, store) => store.patchScene({ mode: a.mode ?? mode }),
    affects: [],
  };
}

export function setAutoKey(on: boolean): Command<OptionsAnswer> {
  return {
    send: (api) => api.options({ autoKey: on }),
    apply: (a, store) => store.patchScene({ autoKey: typeof a.autoKey === 'boolean' ? a.autoKey : on }),
    affects: [],
  };
}

export function undo(redo: boolean): Command<HistoryAnswer> {
  return {
    // 409 (nothing to take: another client took it first) is the caller's: a state, not an error.
    send: (api) => (redo ? api.redo({ expected: [409] }) : api.undo({ expected: [409] })),
    message: (a) => `${redo ? 'Redo' : 'Undo'}: ${a.label ?? ''}`,
    affects: ['everything'],
  };
}

// ------------------------------------------------------------ time and keys

export function setFrame(frame: number): Command<TimeAnswer> {
  return {
    send: (api) => api.time({ frame }),
    apply: (a, store) => store.setTime({ frame: a.frame, time: a.time }),
    affects: ['pose'],
  };
}

export function key(remove: boolean): Command<KeyAnswer> {
  return {
    send: (api) => api.key(remove ? { delete: true } : {}),
    message: (a, store) =>
      `${remove ? 'Deleted key' : 'Keyed'} at frame ${store.scene?.frame ?? ''}; keys: ${(a.frames ?? []).join(', ') || 'none'}`,
    affects: ['keys', 'scene'],
  };
}

// -------------------------------------------------------------- channel box

/** Sets one channel of several nodes (a keyed one is keyed with the value). */
export function setChannel(controls: string[], attr: string, value: number, label: string): Command<ChannelValuesAnswer> {
  return {
    send: (api) => api.channelValues({ controls, attrs: [attr], value }),
    message: (a) => `Set ${label} = ${formatValue(value)}${a.keys?.length ? ' (keyed)' : ''}`,
    affects: ['pose', 'keys', 'scene'],
  };
}

/** Keys (or deletes the key of) one channel of several nodes at the current frame. */
export function keyChannel(controls: string[], attr: string, remove: boolean, label: string): Command<ChannelKeysAnswer> {
  return {
    send: (api) => api.channelKeys(remove ? { controls, attrs: [attr], delete: true } : { controls, attrs: [attr] }),
    message: (_a, store) => `${remove ? 'Deleted the key of' : 'Keyed'} ${label} at frame ${store.scene?.frame ?? ''}`,
    affects: ['pose', 'keys', 'scene'],
  };
}

/** Moves (or copies) the keys of the controls' keying group at frame `from` to frame `to` (the timeline's tick drag). */
export function moveKeys(controls: string[], from: number, to: number, copy: boolean): Command<ChannelKeysAnswer> {
  return {
    send: (api) => api.channelKeys({ controls, moveTo: to, from, copy }),
    message: () => `${copy ? 'Copied' : 'Moved'} the keys at frame ${from} to ${to}`,
    affects: ['pose', 'keys', 'scene'],
  };
}

/** Sets the playback range (saved with the scene). */
export function setPlaybackRange(first: number, last: number): Command<Revised & { playbackRange: [number, number] }> {
  return {
    send: (api) => api.playbackRange({ first, last }),
    apply: (a, store) => store.patchScene({ playbackRange: a.playbackRange }),
    message: (a) => `Playback range ${a.playbackRange[0]}–${a.playbackRange[1]}`,
    affects: ['scene'],
  };
}

/** Saves, removes or selects a named selection set (saves and removes are one undo step each). */
export function selectionSet(req: SelectionSetRequest): Command<SelectionSetsAnswer> {
  const what = { save: 'Saved', remove: 'Removed', select: 'Selected' }[req.op];
  return {
    send: (api) => api.selectionSet(req),
    apply: (a, store) => {
      if (req.op === 'select' && a.selection) store.setSelection(a.selection);
    },
    message: () => `${what} selection set ${req.name}`,
    affects: req.op === 'select' ? ['keys'] : ['scene'],
  };
}

// -------------------------------------------------------------- graph editor

/** Edits, inserts or deletes keys on curves (the graph editor): one request, one undo step. */
export function curveKeys(req: CurveKeysRequest, label: string): Command<CurveKeysAnswer> {
  return {
    send: (api) => api.curveKeys(req),
    message: (a) => `${label}: ${a.changed} key${a.changed === 1 ? '' : 's'}`,
    affects: ['pose', 'keys', 'scene'],
  };
}

// ----------------------------------------------------------- animator tools

/** An animator tool's request (match, mirror, bind pose, tween): one undo step, the pose and keys re-read. */
export function tool<A>(send: (api: Api) => Promise<A>, message: (a: A) => string): Command<A> {
  return { send, message, affects: ['pose', 'keys', 'scene'] };
}

/** A channel value as the channel box shows it. */
export function formatValue(v: number): string {
  return Number.isInteger(v) ? String(v) : v.toFixed(3);
}

// --------------------------------------------------------------------- rigs

export function addRig(definition: string, editMode: boolean): Command<RigAddAnswer> {
  return {
    send: (api) => api.rigAdd({ definition, editMode }),
    message: (a) => `Added rig ${a.rig} v${a.version} (${a.components?.length ?? 0} components)`,
    affects: ['everything'],
  };
}

export function updateRig(rig: string, keepKeys: 'local' | 'world', force: boolean): Command<RigUpdateAnswer> {
  return {
    send: (api) => api.rigUpdate(force ? { rig, keepKeys, force: true } : { rig, keepKeys }),
    message: (a) => `Updated ${rig} ${a.from} → ${a.to}; rebuilt: ${(a.rebuilt ?? []).join(', ') || 'nothing'}`,
    affects: ['everything'],
  };
}

export function removeRig(rig: string): Command<Revised> {
  return {
    send: (api) => api.rigRemove({ rig }),
    message: () => `Removed rig ${rig}`,
    affects: ['everything'],
  };
}

/** Commits rig edit mode, the definition written to `out` (empty: the rig's own file). */
export function commitEdit(rig: string, out: string): Command<RigEditAnswer> {
  return {
    send: (api) => api.rigEdit(out ? { rig, definitionOut: out } : { rig }),
    message: () => `Committed rig edit mode of ${rig}`,
    affects: ['everything'],
  };
}

export function setFeature(rig: string, feature: string, switchName: string, enabled: boolean): Command<RigFeatureAnswer> {
  return {
    send: (api) => api.rigFeature(switchName ? { rig, feature, enabled, switch: switchName } : { rig, feature, enabled }),
    message: () => `${rig}: feature ${feature}${switchName ? '/' + switchName : ''} ${enabled ? 'on' : 'off'}`,
    affects: ['everything'],
  };
}

export function setEditMode(rig: string, on: boolean): Command<RigEditModeAnswer> {
  return {
    send: (api) => api.rigEditMode({ rig, on }),
    message: () => (on ? `${rig} is in rig edit mode: move its controls, then commit` : `${rig} left rig edit mode`),
    affects: ['everything'],
  };
}

export function step(rig: string, target: { to?: number; by?: number }): Command<StepAnswer> {
  return {
    send: (api) => api.rigStep({ rig, ...target }),
    message: (a) => `${rig}: step ${a.position}/${a.steps}${a.step ? ` (${a.step})` : ''}`,
    affects: ['everything'],
  };
}

// -------------------------------------------------------------- definitions

/** Builds (or live-rebuilds) the definition into the scene. */
export function buildDefinition(definition: RigJson): Command<BuildAnswer> {
  return {
    send: (api) => api.buildDefinition({ definition }),
    message: (a) => `Built ${a.rig} (${a.components ? `${a.components.length} components` : `${a.rebuilt?.length ?? 0} rebuilt`})`,
    affects: ['everything'],
  };
}

/** Saves the definition to `path` (relative to the root); a rig built from that file may now be out of date. */
export function saveDefinition(definition: RigJson, path: string): Command<SaveDefinitionAnswer> {
  return {
    send: (api) => api.saveDefinition({ definition, path }),
    affects: ['rigs'],
  };
}

// -------------------------------------------------------------- build graphs

/** Builds the build graph's rig into the scene (or live-rebuilds what changed): one undo step. */
export function buildGraph(graph: BuildGraphJson): Command<GraphBuildAnswer> {
  return {
    send: (api) => api.buildGraph(graph),
    message: (a) => `Built ${a.rig} from the graph (${a.rebuilt?.length ?? 0} rebuilt)`,
    affects: ['everything'],
  };
}

/** Saves the build graph to `path` (a .build.json, relative to the root); a rig built from it may now be out of date. */
export function saveGraph(graph: BuildGraphJson, path: string): Command<GraphSaveAnswer> {
  return {
    send: (api) => api.saveGraph(graph, path),
    affects: ['rigs'],
  };
}
