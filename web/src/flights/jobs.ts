// Upload a data set and follow ingest jobs (WebSocket events, with polling while the socket is down).

import { ApiError, api, isAbort, uploadDataset } from '../api/client';
import { datasetNameFromFile } from '../api/query';
import type { DatasetFormat, Job } from '../api/types';
import { h, mount } from '../lib/dom';
import { formatBytes } from '../lib/format';

export interface JobsEvents {
  /** A job finished (any client's): refresh the data sets; `mine` when this page uploaded it. */
  onJobDone(job: Job, mine: boolean): void;
  onUploadError(err: ApiError): void;
}

const FORMATS: { value: '' | DatasetFormat; label: string }[] = [
  { value: '', label: 'Auto' },
  { value: 'opensky_csv', label: 'OpenSky CSV' },
  { value: 'traffic_json', label: 'traffic JSON' },
  { value: 'so6', label: 'SO6' },
  { value: 'readsb_trace', label: 'readsb trace' },
];

const FINISHED = new Set(['done', 'failed', 'cancelled']);

interface Upload {
  file: File;
  name: string;
  fraction: number;
  abort(): void;
}

export class JobsView {
  private readonly list: HTMLElement;
  private readonly fileInput: HTMLInputElement;
  private readonly format: HTMLSelectElement;
  private readonly name: HTMLInputElement;
  private readonly jobs = new Map<string, Job>();
  private readonly mine = new Set<string>();
  private readonly reported = new Set<string>();
  private uploads: Upload[] = [];
  private socketOpen = false;
  private pollTimer: number | undefined;

  constructor(root: HTMLElement, private readonly events: JobsEvents) {
    this.fileInput = h('input', { type: 'file', class: 'visually-hidden', id: 'upload-file', 'data-testid': 'upload-input', 'data-param': 'name' });
    this.fileInput.addEventListener('change', () => {
      const f = this.fileInput.files?.[0];
      if (f) this.upload(f);
      this.fileInput.value = '';
    });
    this.format = h(
      'select',
      { id: 'upload-format', 'aria-label': 'Format of the uploaded file', 'data-param': 'format' },
      ...FORMATS.map((f) => h('option', { value: f.value }, f.label)),
    );
    this.name = h('input', {
      id: 'upload-name',
      type: 'text',
      placeholder: 'name',
      title: 'Name of the new data set (a-z 0-9 _ -); empty: from the file name',
      pattern: '[a-z0-9_\\-]{1,64}',
      autocomplete: 'off',
      spellcheck: 'false',
      'aria-label': 'Name of the new data set',
      'data-testid': 'upload-name',
      'data-param': 'name',
    });
    this.list = h('ul', { class: 'job-list', 'data-testid': 'job-list', 'aria-live': 'polite' });
    root.append(
      h(
        'div',
        { class: 'upload-row' },
        h('label', { class: 'btn', for: 'upload-file', title: 'SO6, OpenSky CSV, traffic JSON or a readsb trace; plain or gzip' }, 'Upload…', this.fileInput),
        this.format,
        this.name,
      ),
      h('div', { id: 'upload-error' }),
      this.list,
    );
    this.render();
  }

  setSocketOpen(open: boolean): void {
    this.socketOpen = open;
    this.schedulePoll();
  }

  /** A job event from the WebSocket (or from polling). */
  update(job: Job): void {
    // Events may arrive out of order (e.g. "queued" after "running"); a job never goes back.
    const prev = this.jobs.get(job.id);
    if (prev && (stateRank(job.state) < stateRank(prev.state) || (job.state === prev.state && job.stage === prev.stage && job.progress < prev.progress))) return;
    this.jobs.set(job.id, job);
    if (FINISHED.has(job.state) && !this.reported.has(job.id)) {
      this.reported.add(job.id);
      this.events.onJobDone(job, this.mine.has(job.id));
    }
    this.render();
    this.schedulePoll();
  }

  private upload(file: File) {
    const name = this.name.value.trim() || datasetNameFromFile(file.name);
    this.name.value = '';
    const format = (this.format.value || undefined) as DatasetFormat | undefined;
    const handle = uploadDataset(file, {
      name,
      format,
      onProgress: (f) => {
        up.fraction = f;
        this.render();
      },
    });
    const up: Upload = { file, name, fraction: 0, abort: handle.abort };
    this.uploads.push(up);
    this.render();
    handle.done
      .then((job) => {
        this.mine.add(job.id);
        this.update(job);
      })
      .catch((e: unknown) => {
        if (!isAbort(e)) this.events.onUploadError(e instanceof ApiError ? e : new ApiError(0, { error: 'upload', detail: String(e) }));
      })
      .finally(() => {
        this.uploads = this.uploads.filter((u) => u !== up);
        this.render();
      });
  }

  /** Polls unfinished jobs while the socket is down (1 s), so progress never stalls silently. */
  private schedulePoll() {
    window.clearTimeout(this.pollTimer);
    const pending = [...this.jobs.values()].filter((j) => !FINISHED.has(j.state));
    if (this.socketOpen || pending.length === 0) return;
    this.pollTimer = window.setTimeout(() => {
      for (const j of pending) {
        api
          .job(j.id)
          .then((next) => this.update(next))
          .catch(() => this.schedulePoll());
      }
    }, 1000);
  }

  private render() {
    const rows: HTMLElement[] = [];
    for (const u of this.uploads) {
      rows.push(
        h(
          'li',
          { class: 'job', 'data-state': 'uploading' },
          h('div', { class: 'job-line' }, h('span', { class: 'job-name', title: u.file.name }, u.name), h('span', { class: 'job-state' }, `uploading · ${formatBytes(u.file.size)}`)),
          progress(u.fraction, `Uploading ${u.file.name}`),
          h('button', { type: 'button', class: 'link-button', onclick: () => u.abort() }, 'Cancel'),
        ),
      );
    }
    const jobs = [...this.jobs.values()].reverse().slice(0, 8);
    for (const j of jobs) {
      const active = !FINISHED.has(j.state);
      rows.push(
        h(
          'li',
          { class: `job ${j.state}`, 'data-job-id': j.id, 'data-state': j.state },
          h(
            'div',
            { class: 'job-line' },
            // Ingest jobs are named by the data set they create; others by what they do and to what.
            h('span', { class: 'job-name', title: `${j.kind} ${j.id}` }, j.kind === 'ingest' ? j.dataset || j.id : `${j.kind} ${j.dataset || j.id}`),
            h('span', { class: 'job-state' }, active ? `${j.stage || j.state} · ${Math.round(j.progress * 100)}%` : j.state),
          ),
          active || j.state === 'done' ? progress(j.state === 'done' ? 1 : j.progress, `${j.kind} ${j.dataset}`) : null,
          j.error ? h('div', { class: 'error-text small' }, j.error.detail || j.error.error) : null,
          active
            ? h('button', { type: 'button', class: 'link-button', onclick: () => void api.cancelJob(j.id).catch(() => undefined) }, 'Cancel')
            : h('button', { type: 'button', class: 'link-button', onclick: () => this.dismiss(j.id) }, 'Dismiss'),
        ),
      );
    }
    mount(this.list, ...rows);
    this.list.hidden = rows.length === 0;
  }

  private dismiss(id: string) {
    this.jobs.delete(id);
    this.render();
  }
}

function stateRank(s: Job['state']): number {
  return s === 'queued' ? 0 : s === 'running' ? 1 : 2;
}

function progress(fraction: number, label: string): HTMLElement {
  const pct = Math.round(Math.min(1, Math.max(0, fraction)) * 100);
  return h(
    'div',
    { class: 'progress', role: 'progressbar', 'aria-label': label, 'aria-valuemin': 0, 'aria-valuemax': 100, 'aria-valuenow': pct },
    h('div', { class: 'progress-fill', style: `width:${pct}%` }),
  );
}
