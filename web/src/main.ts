import './styles.css';
import { App, showFatal } from './app';

try {
  new App();
} catch (e) {
  console.error(e);
  showFatal(e);
}
